#!/usr/bin/env python3
"""A variant of a bag from rfm_carmen2bag, for checking the map on data unlike the recording:

    scripts/perturb_bag.py IN.bag OUT.bag VARIANT

VARIANT is one of
    half     every second scan of /scan (a logger that keeps fewer scans)
    beams2   every second beam, the increment doubled (a lidar of half the angular resolution)
    noise    the odom -> base_link poses of /tf with Gaussian noise, 3 cm and 0.7 deg, seeded
             (poses corrected less well)
    short    returns beyond 8 m become +inf, range_max 8 m (a short-range lidar)
Other topics are copied unchanged. Needs python3-rosbag.
"""
import math
import random
import sys

import rosbag

from sim_bag_io import yaw_of

SHORT_RANGE = 8.0  # m
NOISE_XY = 0.03  # m
NOISE_YAW = math.radians(0.7)
VARIANTS = ("half", "beams2", "noise", "short")


def main():
    if len(sys.argv) != 4 or sys.argv[3] not in VARIANTS:
        sys.exit(__doc__)
    source, target, variant = sys.argv[1:]
    noise = random.Random(7)
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
            elif topic == "/tf" and variant == "noise":
                for tf in msg.transforms:
                    if tf.child_frame_id.lstrip("/") != "base_link":
                        continue
                    tf.transform.translation.x += noise.gauss(0.0, NOISE_XY)
                    tf.transform.translation.y += noise.gauss(0.0, NOISE_XY)
                    yaw = yaw_of(tf.transform.rotation) + noise.gauss(0.0, NOISE_YAW)
                    q = tf.transform.rotation
                    q.x, q.y, q.z, q.w = 0.0, 0.0, math.sin(0.5 * yaw), math.cos(0.5 * yaw)
            out.write(topic, msg, stamp)


if __name__ == "__main__":
    main()
