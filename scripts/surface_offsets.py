#!/usr/bin/env python3
"""How far from the true surfaces a map draws its static and glass cells.

The class metrics count a drawn cell right when the true material lies within one cell of it. A
cell drawn two cells off a wall or pane is mostly the range noise's tail: a single echo that
ended behind the surface, which no later ray misses (rays do not reach behind a wall). Reads the
output of scripts/run_random_evaluation.sh (OUT/SETUP/SEED/MAPPER/{classes.pgm,
truth_cells.pgm}) and sorts the static and glass cells of each MAPPER by their Chebyshev distance
to the nearest cell holding any true surface: at most 1, exactly 2, 3 or more.

    scripts/surface_offsets.py OUT [MAPPER ...]    # MAPPER: RFM (default), plain_grid

Prints one markdown table: a row per mapper, setup and seed split. Run it on a map made with true
poses (FIXED_FRAME=map): in odom the drift moves whole walls.
Needs python3-numpy.
"""
import os
import sys

import numpy as np

from sim_bag_io import read_manifest, read_pgm_grid
from unseen_glass import within_one

STATIC, GLASS = 2, 3  # classes.pgm codes
DRAWN = [("static", STATIC), ("glass", GLASS)]


def offsets(directory, mapper):
    """Per drawn class: [cells within 1, at 2, at 3 or more] of a true surface."""
    map_dir = os.path.join(directory, mapper)
    classes = read_pgm_grid(os.path.join(map_dir, "classes.pgm"))
    truth = read_pgm_grid(os.path.join(map_dir, "truth_cells.pgm"))
    if truth.shape != classes.shape:
        raise SystemExit("%s: truth_cells.pgm is not classes.pgm's size" % map_dir)
    near = within_one(truth != 0)
    near_two = within_one(near)  # a 3 x 3 dilation twice: within Chebyshev distance 2
    counts = {}
    for name, code in DRAWN:
        drawn = classes == code
        counts[name] = [int(np.sum(drawn & near)), int(np.sum(drawn & near_two & ~near)),
                        int(np.sum(drawn & ~near_two))]
    return counts


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    mappers = sys.argv[2:] or ["RFM"]
    rows = {}
    for config, seed, setup, split in read_manifest(out):
        if config not in mappers:
            continue
        row = rows.setdefault((config, setup, split),
                              {"seeds": 0, "counts": {name: [0, 0, 0] for name, _ in DRAWN}})
        row["seeds"] += 1
        for name, cells in offsets(os.path.join(out, setup, seed), config).items():
            row["counts"][name] = [a + b for a, b in zip(row["counts"][name], cells)]
    print("| mapper | setup | seeds | static cells | within 1 / 2 / 3+ cells of a surface (%) "
          "| glass cells | within 1 / 2 / 3+ cells of a surface (%) |")
    print("|---|---|---|---:|---|---:|---|")
    for (config, setup, split), row in sorted(rows.items()):
        columns = []
        for name, _ in DRAWN:
            cells = row["counts"][name]
            total = sum(cells)
            shares = " / ".join("%.1f" % (100.0 * c / total) for c in cells) if total else "-"
            columns += [str(total), shares]
        print("| %s | %s | %s (%d) | %s |" % (config, setup, split, row["seeds"],
                                              " | ".join(columns)))


if __name__ == "__main__":
    main()
