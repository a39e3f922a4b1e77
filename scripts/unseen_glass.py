#!/usr/bin/env python3
"""Which true glass cells a map missed, and whether the lidar ever saw them.

Glass returns only near its normal (and, dirty, now and then from anywhere): a pane the robot
never faced crosses every ray that reaches it without an echo, and no map can draw it from those
rays. Reads the output of scripts/run_random_evaluation.sh (OUT/SETUP/SEED/{sim.bag,
MAPPER/classes.pgm, MAPPER/map.yaml, MAPPER/truth_cells.pgm}: rfm_eval --truth-cells writes the
last) and sorts the true glass cells that rfm_eval's class metrics count (glass alone in the cell,
something other than unknown drawn within one cell) by the direct glass echoes (RayTruth.GLASS,
placed with the true poses) that ended within one cell of them: none, 1-9 (a dirty pane's
scatter, a glimpse) or at least 10. For each it gives the share of those cells and how many of
them the map draws glass within one cell (as the class metrics' glass recall does), and what the
map draws instead at the cells seen with 10 echoes or more.

    scripts/unseen_glass.py OUT [MAPPER]    # MAPPER: RFM (default)

Prints one markdown table: a row per setup and seed split. The class map carries the odometry's
drift when it was made in odom, as the class metrics do; the echoes are placed with true poses.
Needs python3-rosbag, python3-numpy and python3-yaml.
"""
import os
import sys

import numpy as np

from sim_bag_io import (NO_RETURN, read_manifest, read_map_geometry, read_pgm_grid,
                        read_scans_in_map)

GLASS_ECHO = 2  # RayTruth.GLASS
GLASS_BIT = 2  # rfm::sim::kGlassBit
UNKNOWN, FREE, STATIC, GLASS, METAL, MOTION = range(6)  # classes.pgm codes
BUCKETS = ["no echo", "1-9 echoes", "10 or more"]
MISSED = ["static", "metal", "motion", "free"]  # what a seen pane not drawn glass is drawn


def within_one(mask):
    """Cells with `mask` set in them or in one of their 8 neighbours."""
    return sum_within_one(mask.astype(np.int64)) > 0


def sum_within_one(counts):
    """Each cell's count summed with its 8 neighbours'."""
    padded = np.pad(counts, 1)
    out = np.zeros_like(counts)
    for dy in (0, 1, 2):
        for dx in (0, 1, 2):
            out += padded[dy:dy + counts.shape[0], dx:dx + counts.shape[1]]
    return out


def glass_echoes(bag_path, shape, origin, resolution):
    """Direct glass echoes per cell of the map's grid, placed with the true poses."""
    counts = np.zeros(shape, dtype=np.int64)
    scans, _ = read_scans_in_map(bag_path)
    for scan in scans:
        beams = np.nonzero((scan["truth"] == GLASS_ECHO) & (scan["ranges"] < NO_RETURN))[0]
        if not len(beams):
            continue
        r = scan["ranges"][beams]
        x = np.floor((scan["x"] + r * scan["cos"][beams] - origin[0]) / resolution).astype(int)
        y = np.floor((scan["y"] + r * scan["sin"][beams] - origin[1]) / resolution).astype(int)
        inside = (x >= 0) & (y >= 0) & (x < shape[1]) & (y < shape[0])
        np.add.at(counts, (y[inside], x[inside]), 1)
    return counts


def count_run(directory, mapper):
    """[cells, drawn glass] per bucket of one simulated run, and of the cells with 10 or more
    echoes not drawn glass, how many are drawn each of MISSED (the first class found within one
    cell, in that order; free also counts unknown)."""
    map_dir = os.path.join(directory, mapper)
    classes = read_pgm_grid(os.path.join(map_dir, "classes.pgm"))
    truth = read_pgm_grid(os.path.join(map_dir, "truth_cells.pgm"))
    if truth.shape != classes.shape:
        raise SystemExit("%s: truth_cells.pgm is not classes.pgm's size" % map_dir)
    origin, resolution = read_map_geometry(map_dir)
    echoes = sum_within_one(glass_echoes(os.path.join(directory, "sim.bag"), classes.shape,
                                         origin, resolution))
    counted = (truth == GLASS_BIT) & within_one(classes != UNKNOWN)
    drawn = within_one(classes == GLASS)
    bucket = np.where(echoes == 0, 0, np.where(echoes < 10, 1, 2))
    counts = [[int(np.sum(counted & (bucket == b))), int(np.sum(counted & (bucket == b) & drawn))]
              for b in range(len(BUCKETS))]
    left = counted & (bucket == 2) & ~drawn
    missed = []
    for code in (STATIC, METAL, MOTION):
        here = left & within_one(classes == code)
        missed.append(int(np.sum(here)))
        left &= ~here
    missed.append(int(np.sum(left)))
    return counts, missed


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    mapper = sys.argv[2] if len(sys.argv) > 2 else "RFM"
    rows = {}
    for config, seed, setup, split in read_manifest(out):
        if config != mapper:
            continue
        row = rows.setdefault((setup, split), {"seeds": 0, "counts": [[0, 0] for _ in BUCKETS],
                                               "missed": [0] * len(MISSED)})
        row["seeds"] += 1
        counts, missed = count_run(os.path.join(out, setup, seed), mapper)
        for b, (cells, drawn) in enumerate(counts):
            row["counts"][b][0] += cells
            row["counts"][b][1] += drawn
        row["missed"] = [a + b for a, b in zip(row["missed"], missed)]
    print("| setup | seeds | true glass cells | by the glass echoes within a cell (%): "
          + " / ".join(BUCKETS) + " | drawn glass (recall, %): all / "
          + " / ".join(BUCKETS) + " | 10 or more, not drawn glass, drawn (%): "
          + " / ".join(MISSED) + " |")
    print("|---|---|---:|---|---|---|")
    for (setup, split), row in sorted(rows.items()):
        counts = row["counts"]
        total = sum(c[0] for c in counts)
        shares = " / ".join("%.1f" % (100.0 * c[0] / max(total, 1)) for c in counts)
        recall = " / ".join("%.1f" % (100.0 * c[1] / c[0]) if c[0] else "-" for c in counts)
        missed = " / ".join("%.1f" % (100.0 * m / max(sum(row["missed"]), 1))
                            for m in row["missed"])
        print("| %s | %s (%d) | %d | %s | %.1f / %s | %s |" % (
            setup, split, row["seeds"], total, shares,
            100.0 * sum(c[1] for c in counts) / max(total, 1), recall, missed))


if __name__ == "__main__":
    main()
