#!/usr/bin/env python3
"""A variant of a bag from rfm_carmen2bag, for checking the map on data unlike the recording:

    scripts/perturb_bag.py IN.bag OUT.bag VARIANT

VARIANT is one of
    half     every second scan of /scan (a logger that keeps fewer scans)
    beams2   every second beam, the increment doubled (a lidar of half the angular resolution)
    noise    the odom -> base_link poses of /tf with Gaussian noise, 3 cm and 0.7 deg, seeded
             (poses corrected less well)
    short    returns beyond 8 m become +inf, range_max 8 m (a short-range lidar)
    drift    the odom -> base_link poses of /tf as wheel odometry reads the path: every step
             between them with the simulator's default drift (include/reflectance_field_map/
             sim/odometry.h, a calibrated wheelchair), seeded (a robot with no localiser)
Other topics are copied unchanged. Prints the drift at the end for `drift`. Needs python3-rosbag.
"""
import math
import random
import sys

import rosbag

from sim_bag_io import yaw_of

SHORT_RANGE = 8.0  # m
NOISE_XY = 0.03  # m
NOISE_YAW = math.radians(0.7)
VARIANTS = ("half", "beams2", "noise", "short", "drift")

# rfm::sim::OdometryDrift's defaults.
DRIFT_XY_NOISE = 0.005  # m per sqrt(m) driven
DRIFT_YAW_NOISE_DEG = 0.1  # per sqrt(m) driven
DRIFT_TURN_NOISE_DEG = 0.05  # per sqrt(deg) turned
DRIFT_SCALE_ERROR = 0.01
DRIFT_TURN_SCALE_ERROR = 0.005
DRIFT_YAW_BIAS_DEG_PER_M = 0.02


def wrap(angle):
    return math.atan2(math.sin(angle), math.cos(angle))


class WheelOdometry:
    """Reads a path step by step as rfm::sim::OdometryModel does with its default drift."""

    def __init__(self, rng):
        self.rng = rng
        self.truth = None  # the last true pose (x, y, yaw)
        self.pose = None  # the odometry's pose

    def advance(self, truth):
        if self.truth is None:
            self.truth = self.pose = truth
            return truth
        c, s = math.cos(self.truth[2]), math.sin(self.truth[2])
        wx, wy = truth[0] - self.truth[0], truth[1] - self.truth[1]
        step_x, step_y = c * wx + s * wy, -s * wx + c * wy  # in the previous true pose's frame
        turn = wrap(truth[2] - self.truth[2])
        self.truth = truth
        driven = math.hypot(step_x, step_y)
        xy_sigma = DRIFT_XY_NOISE * math.sqrt(driven)
        yaw_sigma_deg = math.sqrt(DRIFT_YAW_NOISE_DEG ** 2 * driven +
                                  DRIFT_TURN_NOISE_DEG ** 2 * abs(math.degrees(turn)))
        read_x = step_x * (1.0 + DRIFT_SCALE_ERROR) + xy_sigma * self.rng.gauss(0.0, 1.0)
        read_y = step_y * (1.0 + DRIFT_SCALE_ERROR) + xy_sigma * self.rng.gauss(0.0, 1.0)
        read_yaw = turn * (1.0 + DRIFT_TURN_SCALE_ERROR) + math.radians(
            DRIFT_YAW_BIAS_DEG_PER_M * driven + yaw_sigma_deg * self.rng.gauss(0.0, 1.0))
        x, y, yaw = self.pose
        c, s = math.cos(yaw), math.sin(yaw)
        self.pose = (x + c * read_x - s * read_y, y + s * read_x + c * read_y, yaw + read_yaw)
        return self.pose


def main():
    if len(sys.argv) != 4 or sys.argv[3] not in VARIANTS:
        sys.exit(__doc__)
    source, target, variant = sys.argv[1:]
    noise = random.Random(7)
    odometry = WheelOdometry(random.Random(11))
    scans = 0
    with rosbag.Bag(source) as bag, rosbag.Bag(target, "w") as out:
        for topic, msg, stamp in bag.read_messages():
            if topic == "/scan":
                scans += 1
                if variant == "half" and scans % 2 == 0:
                    continue
                if variant == "beams2":
                    msg.ranges = msg.ranges[::2]
                    msg.intensities = msg.intensities[::2]
                    msg.angle_increment *= 2
                    msg.angle_max = msg.angle_min + msg.angle_increment * (len(msg.ranges) - 1)
                elif variant == "short":
                    msg.range_max = min(msg.range_max, SHORT_RANGE)
                    msg.ranges = [r if r <= SHORT_RANGE else math.inf for r in msg.ranges]
            elif topic == "/tf" and variant in ("noise", "drift"):
                for tf in msg.transforms:
                    if tf.child_frame_id.lstrip("/") != "base_link":
                        continue
                    t = tf.transform.translation
                    if variant == "noise":
                        x = t.x + noise.gauss(0.0, NOISE_XY)
                        y = t.y + noise.gauss(0.0, NOISE_XY)
                        yaw = yaw_of(tf.transform.rotation) + noise.gauss(0.0, NOISE_YAW)
                    else:
                        x, y, yaw = odometry.advance((t.x, t.y, yaw_of(tf.transform.rotation)))
                    t.x, t.y = x, y
                    q = tf.transform.rotation
                    q.x, q.y, q.z, q.w = 0.0, 0.0, math.sin(0.5 * yaw), math.cos(0.5 * yaw)
            out.write(topic, msg, stamp)
    if variant == "drift" and odometry.truth is not None:
        (tx, ty, tyaw), (ox, oy, oyaw) = odometry.truth, odometry.pose
        print("drift at the end: %.2f m, %.1f deg" %
              (math.hypot(ox - tx, oy - ty), abs(math.degrees(wrap(oyaw - tyaw)))))


if __name__ == "__main__":
    main()
