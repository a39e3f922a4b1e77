#!/usr/bin/env python3
"""Joins simulated scene bags into one long drive for the soak test.

The scenes are laid side by side along x (SPACING m apart) and visited in turn, lap after lap,
until DURATION seconds of recording are made: each scene's messages keep their order and timing,
shifted to follow the previous one in time and in space, and between scenes the robot drives to
the next scene's start in a straight line (odometry only, at 1.5 m/s), so time and poses run on
without a jump: a replay gives the mapper a long continuous recording that revisits every place.

  compose_bag.py --out LONG.bag --duration 3600 [--spacing 60] SCENE.bag [SCENE.bag ...]

Only /scan_front, /scan_rear, /tf and /tf_static are kept. Scans are numbered (header.seq) one
after the other on each topic, as a driver numbers them, so that the node can count any it loses
in a queue.
"""
import argparse
import copy
import json
import math
import sys

import rosbag
import rospy
from tf2_msgs.msg import TFMessage

SCAN_TOPICS = ("/scan_front", "/scan_rear")
TRANSIT_SPEED = 1.5  # m/s
TRANSIT_RATE = 20.0  # Hz of odometry while driving between scenes


class Scene:
    def __init__(self, path):
        self.path = path
        self.messages = []  # (topic, msg, bag time)
        self.statics = None
        with rosbag.Bag(path) as bag:
            for topic, msg, t in bag.read_messages(topics=list(SCAN_TOPICS) + ["/tf", "/tf_static"]):
                if topic == "/tf_static":
                    self.statics = msg
                    continue
                self.messages.append((topic, msg, t))
        if not self.messages:
            sys.exit("compose_bag.py: %s holds no scans or TF" % path)
        self.begin = self.messages[0][2]
        self.end = self.messages[-1][2]
        odometry = [tf for topic, msg, _ in self.messages if topic == "/tf"
                    for tf in msg.transforms if tf.child_frame_id.lstrip("/") == "base_link"]
        if not odometry:
            sys.exit("compose_bag.py: %s has no odometry (odom -> base_link)" % path)
        self.first_pose = pose(odometry[0])
        self.last_pose = pose(odometry[-1])


def pose(transform):
    q = transform.transform.rotation
    yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
    return (transform.transform.translation.x, transform.transform.translation.y, yaw)


def odometry(stamp, x, y, yaw, template):
    tf = copy.deepcopy(template)
    tf.header.stamp = stamp
    tf.transform.translation.x = x
    tf.transform.translation.y = y
    tf.transform.rotation.x = 0.0
    tf.transform.rotation.y = 0.0
    tf.transform.rotation.z = math.sin(yaw / 2.0)
    tf.transform.rotation.w = math.cos(yaw / 2.0)
    return tf


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True)
    parser.add_argument("--duration", type=float, required=True)
    parser.add_argument("--spacing", type=float, default=60.0)
    parser.add_argument("--summary", help="also write a JSON summary here (scans, laps, lap_s)")
    parser.add_argument("scenes", nargs="+")
    args = parser.parse_args()

    scenes = [Scene(path) for path in args.scenes]
    template = None
    for scene in scenes:
        for topic, msg, _ in scene.messages:
            if topic == "/tf":
                template = next(tf for tf in msg.transforms
                                if tf.child_frame_id.lstrip("/") == "base_link")
                break
        if template is not None:
            break
    start = scenes[0].begin
    now = start
    previous_end = None  # global pose where the last scene left the robot
    laps = 0
    scans = 0
    lap_seconds = None
    seq = {topic: 0 for topic in SCAN_TOPICS}
    with rosbag.Bag(args.out, "w") as out:
        out.write("/tf_static", scenes[0].statics, start)
        while (now - start).to_sec() < args.duration:
            for index, scene in enumerate(scenes):
                dx = index * args.spacing
                sx, sy, syaw = scene.first_pose
                if previous_end is not None:
                    # Drive from where the robot is to the next scene's start.
                    px, py, pyaw = previous_end
                    distance = math.hypot(sx + dx - px, sy - py)
                    seconds = max(2.0, distance / TRANSIT_SPEED)
                    steps = int(seconds * TRANSIT_RATE)
                    turn = math.atan2(math.sin(syaw - pyaw), math.cos(syaw - pyaw))
                    for step in range(1, steps + 1):
                        f = step / float(steps)
                        stamp = now + rospy.Duration(step / TRANSIT_RATE)
                        tf_msg = TFMessage(transforms=[odometry(
                            stamp, px + f * (sx + dx - px), py + f * (sy - py), pyaw + f * turn,
                            template)])
                        out.write("/tf", tf_msg, stamp)
                    now = now + rospy.Duration(steps / TRANSIT_RATE + 1.0 / TRANSIT_RATE)
                shift = now - scene.begin
                for topic, msg, t in scene.messages:
                    msg = copy.deepcopy(msg)
                    if topic == "/tf":
                        for tf in msg.transforms:
                            tf.header.stamp = tf.header.stamp + shift
                            if tf.child_frame_id.lstrip("/") == "base_link":
                                tf.transform.translation.x += dx
                    else:
                        msg.header.stamp = msg.header.stamp + shift
                        seq[topic] += 1
                        msg.header.seq = seq[topic]
                        scans += 1
                    out.write(topic, msg, t + shift)
                now = scene.end + shift + rospy.Duration(0.01)
                lx, ly, lyaw = scene.last_pose
                previous_end = (lx + dx, ly, lyaw)
                if (now - start).to_sec() >= args.duration:
                    break
            laps += 1
            if lap_seconds is None:
                lap_seconds = (now - start).to_sec()
    if args.summary:
        with open(args.summary, "w") as f:
            json.dump({"scans": scans, "laps": laps, "lap_s": lap_seconds,
                       "duration_s": (now - start).to_sec(), "start_s": start.to_sec()}, f)
    print("compose_bag.py: %s: %.0f s, %d scans, %d laps of %d scenes" %
          (args.out, (now - start).to_sec(), scans, laps, len(scenes)))


if __name__ == "__main__":
    main()
