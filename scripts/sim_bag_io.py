"""Reading the simulator's bags and the mappers' label bags, for the evaluation scripts.

A scan is keyed by (topic, stamp in ns), as /sim/ray_truth and /rfm/ray_labels name it.
"""
import bisect
import math

import numpy as np
import rosbag


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def compose(a, b):
    """Planar pose a then b, each (x, y, yaw)."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


class PoseTrack:
    """The poses of one /tf link in stamp order."""

    def __init__(self):
        self.stamps, self.poses = [], []

    def add(self, stamp, pose):
        self.stamps.append(stamp)
        self.poses.append(pose)

    def at(self, stamp):
        """The first pose stamped at or after `stamp`, else the last."""
        return self.poses[min(bisect.bisect_left(self.stamps, stamp), len(self.poses) - 1)]


def read_transforms_and_truth(bag_path, chains):
    """A PoseTrack per /tf link in `chains` ((parent, child) pairs); /tf_static's poses by child
    frame; the truth of every scan by key."""
    poses = {chain: PoseTrack() for chain in chains}
    mounts, truth = {}, {}
    with rosbag.Bag(bag_path) as bag:
        for topic, msg, _ in bag.read_messages(topics=["/tf", "/tf_static", "/sim/ray_truth"]):
            if topic == "/sim/ray_truth":
                truth[(msg.scan_topic, msg.header.stamp.to_nsec())] = np.frombuffer(
                    msg.classes, dtype=np.uint8)
                continue
            for tf in msg.transforms:
                pose = (tf.transform.translation.x, tf.transform.translation.y,
                        yaw_of(tf.transform.rotation))
                if topic == "/tf_static":
                    mounts[tf.child_frame_id] = pose
                elif (tf.header.frame_id, tf.child_frame_id) in poses:
                    poses[(tf.header.frame_id, tf.child_frame_id)].add(
                        tf.header.stamp.to_sec(), pose)
    return poses, mounts, truth


def read_labels(path):
    """The labels of every scan of a labels bag (/rfm/ray_labels) by key."""
    labels = {}
    with rosbag.Bag(path) as bag:
        for _, msg, _ in bag.read_messages():
            labels[(msg.scan_topic, msg.header.stamp.to_nsec())] = np.frombuffer(
                msg.labels, dtype=np.uint8)
    return labels
