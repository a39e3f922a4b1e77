"""Reading the simulator's bags and the mappers' label bags, for the evaluation scripts.

A scan is keyed by (topic, stamp in ns), as /sim/ray_truth and /rfm/ray_labels name it.
"""
import bisect
import math
import os

import numpy as np
import rosbag

NO_RETURN = 1e9  # m: the range a beam without a return (+inf) is read as


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


def read_scans_in_map(bag_path):
    """Every scan of a simulated bag with its sensor's true pose (map frame), its beams' directions
    and ranges (NO_RETURN for +inf) and its truth, in bag order, and the stamp of scene time 0 (the
    bag's start)."""
    chains, mounts, truth = read_transforms_and_truth(
        bag_path, [("map", "odom"), ("odom", "base_link")])
    scans = []
    with rosbag.Bag(bag_path) as bag:
        origin = bag.get_start_time()
        for topic, msg, _ in bag.read_messages():
            if not hasattr(msg, "ranges"):
                continue
            key = (topic, msg.header.stamp.to_nsec())
            if key not in truth:
                continue
            stamp = msg.header.stamp.to_sec()
            pose = compose(compose(chains[("map", "odom")].at(stamp),
                                   chains[("odom", "base_link")].at(stamp)),
                           mounts[msg.header.frame_id])
            ranges = np.nan_to_num(np.array(msg.ranges), posinf=NO_RETURN)
            angles = pose[2] + msg.angle_min + msg.angle_increment * np.arange(len(ranges))
            scans.append({"key": key, "stamp": stamp, "x": pose[0], "y": pose[1],
                          "cos": np.cos(angles), "sin": np.sin(angles), "ranges": ranges,
                          "truth": truth[key]})
    return scans, origin


def read_map_geometry(directory):
    """The origin (x, y in m) and the resolution of DIR/map.yaml."""
    meta = {}
    for line in open(directory + "/map.yaml"):
        key, _, value = line.partition(":")
        meta[key.strip()] = value.strip()
    origin = [float(v) for v in meta["origin"].strip("[]").split(",")[:2]]
    return origin, float(meta["resolution"])


def read_pgm_grid(path):
    """A binary PGM (P5, one byte a pixel) as rows from the map's y = 0 up (the picture's bottom
    row first), as classes.pgm and rfm_eval --truth-cells write them."""
    data = open(path, "rb").read()
    fields, position = [], 0
    while len(fields) < 4:
        end = data.index(b"\n", position)
        line = data[position:end]
        position = end + 1
        if not line.startswith(b"#"):
            fields += line.split()
    if fields[0] != b"P5" or fields[3] != b"255":
        raise SystemExit("%s: not a binary PGM of one byte a pixel" % path)
    width, height = int(fields[1]), int(fields[2])
    pixels = np.frombuffer(data[position:position + width * height], dtype=np.uint8)
    if width < 1 or height < 1 or len(pixels) != width * height:
        raise SystemExit("%s: %d bytes for %d x %d pixels" % (path, len(pixels), width, height))
    return pixels.reshape(height, width)[::-1]


def read_manifest(out):
    """The runs listed in OUT/manifest.txt of scripts/run_random_evaluation.sh, in its order:
    (mapper, seed, setup, split) each."""
    path = os.path.join(out, "manifest.txt")
    if not os.path.exists(path):
        raise SystemExit("%s not found: OUT is scripts/run_random_evaluation.sh's" % path)
    with open(path) as manifest:
        return [(mapper, seed, setup, split)
                for mapper, seed, _, setup, split in (line.split() for line in manifest)]


def scenes_mapped_by(out, mappers):
    """{(setup, seed): split} of the scenes in OUT/manifest.txt that every one of `mappers`
    mapped."""
    splits, mapped = {}, {}
    for mapper, seed, setup, split in read_manifest(out):
        splits[(setup, seed)] = split
        mapped.setdefault((setup, seed), set()).add(mapper)
    return {scene: split for scene, split in splits.items() if set(mappers) <= mapped[scene]}
