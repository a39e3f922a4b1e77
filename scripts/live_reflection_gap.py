#!/usr/bin/env python3
"""Why the node's labels keep reflections that the offline map removes.

    scripts/live_reflection_gap.py OUT [--offline RFM] [--live RFM_live] [--every N]

OUT is scripts/run_random_evaluation.sh's scratch directory: per scene OUT/SETUP/SEED holds
sim.bag, the offline map (OUT/.../RFM: rfm_offline) and the live labels (OUT/.../RFM_live:
labels.bag, and classes.bin or classes.bin.gz from rfm_live_labels --classes-log, the classes
each motion-removal pass left). For every reflection beam (simulator truth) that the offline map
labels REFLECTION and the live labels keep, it finds the first cell on the beam that the offline
map draws glass or metal (where the offline map cut it), and what the live map held there at the
last pass before the beam's scan. A cut cell the live map had never drawn as an obstacle before
that scan, and draws glass or metal later, is a pane the node could not know of yet: the live
labels judge each scan when it arrives, the offline ones see the recording whole. Prints a
markdown table per setup and split (beams summed over the seeds); every Nth such beam is scored
(default 5). Both maps must be made in one fixed frame (the evaluation's odom).
"""
import argparse
import bisect
import collections
import gzip
import json
import math
import os
import struct
import sys

import numpy as np
import rosbag

from sim_bag_io import (compose, read_labels, read_map_geometry, read_pgm_grid,
                        read_transforms_and_truth, scenes_mapped_by)

REFLECTION_TRUTH = 5
KEPT, REFLECTION_LABEL = 1, 3
STATIC, GLASS, METAL = 2, 3, 4
CLASS_NAMES = {0: "unknown", 1: "free", 2: "static", 3: "glass", 4: "metal", 5: "motion",
               6: "occupied"}
OBSTACLES = (STATIC, GLASS, METAL)
NEVER = math.inf


def read_offline_classes(directory):
    """classes.pgm with row 0 at the map's origin (y up), the origin (m) and the resolution."""
    origin, resolution = read_map_geometry(directory)
    return read_pgm_grid(directory + "/classes.pgm"), origin, resolution


def read_classes_log(path):
    """The passes of rfm_live_labels --classes-log (gzipped when the name ends in .gz):
    (stamp, min x, min y, classes[y][x])."""
    passes = []
    with (gzip.open if path.endswith(".gz") else open)(path, "rb") as log:
        while True:
            header = log.read(24)
            if len(header) < 24:
                break
            stamp, min_x, min_y, width, height = struct.unpack("=diiii", header)
            if width < 0 or height < 0 or width * height > 1 << 28:
                sys.exit("live_reflection_gap.py: %s: a pass's box is %d x %d" %
                         (path, width, height))
            cells = np.frombuffer(log.read(width * height), dtype=np.uint8)
            if cells.size != width * height:
                sys.exit("live_reflection_gap.py: %s ends inside a pass" % path)
            passes.append((stamp, min_x, min_y, cells.reshape(height, width)))
    return passes


def read_scans(bag_path, live_path, offline_path):
    """Each scan's sensor pose in odom, its truth and both label arrays."""
    chains, mounts, truth = read_transforms_and_truth(bag_path, [("odom", "base_link")])
    live, offline = read_labels(live_path), read_labels(offline_path)
    scans = []
    with rosbag.Bag(bag_path) as bag:
        for topic, msg, _ in bag.read_messages():
            if not hasattr(msg, "ranges"):
                continue
            key = (topic, msg.header.stamp.to_nsec())
            if key not in truth or key not in live or key not in offline:
                continue
            stamp = msg.header.stamp.to_sec()
            pose = compose(chains[("odom", "base_link")].at(stamp),
                           mounts.get(msg.header.frame_id, (0.0, 0.0, 0.0)))
            scans.append({"stamp": stamp, "pose": pose, "angle_min": msg.angle_min,
                          "increment": msg.angle_increment, "ranges": np.array(msg.ranges),
                          "truth": truth[key], "live": live[key], "offline": offline[key]})
    return scans


def classes_log_of(live_dir):
    """The run's classes log, gzipped or not; None when it has none."""
    for name in ("classes.bin.gz", "classes.bin"):
        if os.path.exists(os.path.join(live_dir, name)):
            return os.path.join(live_dir, name)
    return None


def score_run(directory, offline_name, live_name, every):
    """Counts of the scored beams by what the live map held at the offline map's cut."""
    offline_dir = os.path.join(directory, offline_name)
    live_dir = os.path.join(directory, live_name)
    classes, origin, resolution = read_offline_classes(offline_dir)
    height, width = classes.shape
    passes = read_classes_log(classes_log_of(live_dir))
    pass_stamps = [p[0] for p in passes]
    # Per cell of the offline map: when the live map first drew it an obstacle, and when it last
    # drew it glass or metal (pass stamps).
    first_obstacle = np.full(classes.shape, NEVER)
    last_glass = np.full(classes.shape, -NEVER)
    offset = (int(math.floor(origin[0] / resolution + 0.5)),
              int(math.floor(origin[1] / resolution + 0.5)))
    for stamp, min_x, min_y, cells in passes:
        x0, y0 = min_x - offset[0], min_y - offset[1]
        xs = slice(max(0, x0), min(width, x0 + cells.shape[1]))
        ys = slice(max(0, y0), min(height, y0 + cells.shape[0]))
        if xs.start >= xs.stop or ys.start >= ys.stop:
            continue
        part = cells[ys.start - y0:ys.stop - y0, xs.start - x0:xs.stop - x0]
        first_obstacle[ys, xs] = np.where(
            np.isin(part, OBSTACLES) & (first_obstacle[ys, xs] == NEVER), stamp,
            first_obstacle[ys, xs])
        last_glass[ys, xs] = np.where(np.isin(part, (GLASS, METAL)), stamp, last_glass[ys, xs])

    counts = collections.Counter()
    scans = read_scans(os.path.join(directory, "sim.bag"), os.path.join(live_dir, "labels.bag"),
                       os.path.join(offline_dir, "labels.bag"))
    for scan in scans:
        n = min(len(scan["truth"]), len(scan["live"]), len(scan["offline"]))
        beams = np.nonzero((scan["truth"][:n] == REFLECTION_TRUTH) &
                           (scan["offline"][:n] == REFLECTION_LABEL) &
                           (scan["live"][:n] == KEPT))[0]
        counts["gap"] += len(beams)
        k = bisect.bisect_left(pass_stamps, scan["stamp"]) - 1  # the last pass before the scan
        x, y, yaw = scan["pose"]
        for beam in beams[::every]:
            counts["scored"] += 1
            angle = yaw + scan["angle_min"] + beam * scan["increment"]
            t = np.arange(0.0, scan["ranges"][beam], 0.25 * resolution)
            cx = np.floor((x + t * math.cos(angle) - origin[0]) / resolution).astype(int)
            cy = np.floor((y + t * math.sin(angle) - origin[1]) / resolution).astype(int)
            inside = (cx >= 0) & (cx < width) & (cy >= 0) & (cy < height)
            drawn = classes[np.clip(cy, 0, height - 1), np.clip(cx, 0, width - 1)]
            cut = np.nonzero(inside & np.isin(drawn, (GLASS, METAL)))[0]
            if cut.size == 0:
                counts["no glass or metal offline on the beam"] += 1
                continue
            gx, gy = cx[cut[0]], cy[cut[0]]
            if k < 0:
                counts["before the first pass, or outside the window"] += 1
                continue
            _, min_x, min_y, cells = passes[k]
            lx, ly = gx + offset[0] - min_x, gy + offset[1] - min_y
            if not (0 <= lx < cells.shape[1] and 0 <= ly < cells.shape[0]):
                counts["before the first pass, or outside the window"] += 1
            elif cells[ly, lx] == STATIC:
                counts["static live"] += 1
            elif cells[ly, lx] in (GLASS, METAL):
                counts["glass or metal live"] += 1
            elif first_obstacle[gy, gx] < scan["stamp"]:
                counts["an obstacle in an earlier pass"] += 1
            elif last_glass[gy, gx] > scan["stamp"]:
                counts["not yet drawn: glass or metal later"] += 1
            else:
                counts["never glass or metal live"] += 1
    return counts


def reflections_removed(eval_json):
    reflection = json.load(open(eval_json))["classes"]["reflection"]
    return reflection["total"], reflection["total"] - reflection["kept"]


def main():
    parser = argparse.ArgumentParser(usage=__doc__.split("\n")[2].strip())
    parser.add_argument("out", help="run_random_evaluation.sh's OUT")
    parser.add_argument("--offline", default="RFM", help="offline map directory name (RFM)")
    parser.add_argument("--live", default="RFM_live", help="live labels directory name (RFM_live)")
    parser.add_argument("--every", type=int, default=5, help="score every Nth beam (default 5)")
    args = parser.parse_args()
    if args.every < 1:
        sys.exit("live_reflection_gap.py: --every must be >= 1")
    rows = {}
    scenes = scenes_mapped_by(args.out, [args.offline, args.live])
    for (setup, seed), split in sorted(scenes.items()):
        directory = os.path.join(args.out, setup, seed)
        if classes_log_of(os.path.join(directory, args.live)) is None:
            continue
        row = rows.setdefault((setup, split), collections.Counter())
        row["seeds"] += 1
        for key, value in score_run(directory, args.offline, args.live, args.every).items():
            row[key] += value
        for name, mapper in (("offline", args.offline), ("live", args.live)):
            total, removed = reflections_removed(os.path.join(directory, mapper, "eval.json"))
            row["reflections"] += total if name == "offline" else 0
            row["removed " + name] += removed
    columns = ["not yet drawn: glass or metal later", "an obstacle in an earlier pass",
               "never glass or metal live", "static live", "glass or metal live",
               "no glass or metal offline on the beam",
               "before the first pass, or outside the window"]
    print("| setup | seeds | reflections removed, offline / live (%) | removed offline as "
          "reflections, kept live (points) | of those, the live map at the offline cut (%): "
          + " / ".join(columns) + " |")
    print("|---|---|---|---:|---|")
    for (setup, split), c in sorted(rows.items()):
        reflections = max(c["reflections"], 1)
        shares = " / ".join("%.1f" % (100.0 * c[k] / max(c["scored"], 1)) for k in columns)
        print("| %s | %s (%d) | %.2f / %.2f | %.2f | %s |" % (
            setup, split, c["seeds"], 100.0 * c["removed offline"] / reflections,
            100.0 * c["removed live"] / reflections, 100.0 * c["gap"] / reflections, shares))


if __name__ == "__main__":
    main()
