#!/usr/bin/env python3
"""Which true glass cells a map missed, and whether the lidar ever faced them within range.

Glass returns only near its normal, within the scene's return cone (`physics.return_cone_deg`):
the RFM records such an echo in its direction bin, and a pane faced often enough stays an obstacle
however many rays cross it from elsewhere. Its other echoes are faint: a dirty pane's scatter and
the weak echo of glass with nothing behind come back now and then from any direction, in bins that
the rays cross far more often without an echo; and the RFM takes no evidence past its evidence
range (`active_region_radius` of config/default.yaml, 10 m, the paper's range). No map of ray
directions draws a pane from those, so this script counts the face-on echoes: direct glass echoes
(RayTruth.GLASS, placed with the true poses) whose in-plane incidence on the nearest pane of the
scene file is within its return cone (plus half a degree) and whose range is within the evidence
range.

Reads the output of scripts/run_random_evaluation.sh (OUT/SETUP/SEED/{sim.bag, scene.yaml,
MAPPER/classes.pgm, MAPPER/map.yaml, MAPPER/truth_cells.pgm}: rfm_eval --truth-cells writes the
last) and sorts the true glass cells that rfm_eval's class metrics count (glass alone in the cell,
something other than unknown drawn within one cell) by the face-on echoes that ended within one
cell of them: none, 1-9 (a glimpse) or at least 10. For the cells without one it gives the share
that other glass echoes reached (scatter, or face-on from beyond the range). For each bucket it
gives how many of its cells the map draws glass within one cell (as the class metrics' glass
recall does), and what the map draws instead at the cells faced 10 times or more.

    scripts/unseen_glass.py OUT [MAPPER]    # MAPPER: RFM (default)

Prints one markdown table: a row per setup and seed split. The class map carries the odometry's
drift when it was made in odom, as the class metrics do; the echoes are placed with true poses.
Needs python3-rosbag, python3-numpy and python3-yaml.
"""
import os
import sys

import numpy as np
import yaml

from sim_bag_io import (NO_RETURN, read_manifest, read_map_geometry, read_pgm_grid,
                        read_scans_in_map)

GLASS_ECHO = 2  # RayTruth.GLASS
GLASS_BIT = 2  # rfm::sim::kGlassBit
UNKNOWN, FREE, STATIC, GLASS, METAL, MOTION = range(6)  # classes.pgm codes
BUCKETS = ["none", "1-9", "10 or more"]
CONE_MARGIN_DEG = 0.5  # rounding only: a return in the cone has its in-plane incidence within it
NEAR_PANE_M = 0.15  # an echo further than this from every pane belongs to none
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


def glass_panes(scene):
    """The glass of a scene file: ("segment", a, b) per straight stretch and ("arc", centre,
    radius, start_deg, end_deg) per arc."""
    panes = []
    for wall in scene.get("walls", []):
        if wall.get("material") != "glass":
            continue
        if wall["type"] == "arc":
            panes.append(("arc", np.array(wall["center"], float), float(wall["radius"]),
                          float(wall["start_deg"]), float(wall["end_deg"])))
            continue
        points = [np.array(p, float) for p in wall["points"]]
        if wall.get("closed"):
            points.append(points[0])
        panes.extend(("segment", a, b) for a, b in zip(points[:-1], points[1:]))
    return panes


def incidence_deg(panes, x, y, ux, uy):
    """Per echo ending at (x, y) along the unit direction (ux, uy): the angle between the beam
    and the normal of the nearest pane, in the scan plane (90 where no pane is within
    NEAR_PANE_M)."""
    nearest = np.full(x.shape, np.inf)
    incidence = np.full(x.shape, 90.0)
    for pane in panes:
        if pane[0] == "segment":
            a, b = pane[1], pane[2]
            d = b - a
            length2 = float(d @ d)
            if length2 == 0.0:
                continue
            t = np.clip(((x - a[0]) * d[0] + (y - a[1]) * d[1]) / length2, 0.0, 1.0)
            distance = np.hypot(x - a[0] - t * d[0], y - a[1] - t * d[1])
            nx, ny = -d[1] / np.sqrt(length2), d[0] / np.sqrt(length2)
            cosine = np.abs(ux * nx + uy * ny)
        else:
            centre, radius, start, end = pane[1:]
            vx, vy = x - centre[0], y - centre[1]
            r = np.maximum(np.hypot(vx, vy), 1e-9)
            on_arc = (np.degrees(np.arctan2(vy, vx)) - start) % 360.0 <= end - start
            distance = np.where(on_arc, np.abs(r - radius), np.inf)
            cosine = np.abs(ux * vx + uy * vy) / r
        closer = distance < nearest
        nearest = np.where(closer, distance, nearest)
        incidence = np.where(closer, np.degrees(np.arccos(np.clip(cosine, 0.0, 1.0))), incidence)
    return np.where(nearest <= NEAR_PANE_M, incidence, 90.0)


def glass_echoes(bag_path, panes, cone_deg, evidence_range, shape, origin, resolution):
    """Direct glass echoes per cell of the map's grid, placed with the true poses: (all of them,
    the face-on ones: within the return cone and the evidence range)."""
    every = np.zeros(shape, dtype=np.int64)
    face_on = np.zeros(shape, dtype=np.int64)
    scans, _ = read_scans_in_map(bag_path)
    for scan in scans:
        beams = np.nonzero((scan["truth"] == GLASS_ECHO) & (scan["ranges"] < NO_RETURN))[0]
        if not len(beams):
            continue
        r = scan["ranges"][beams]
        ux, uy = scan["cos"][beams], scan["sin"][beams]
        ex, ey = scan["x"] + r * ux, scan["y"] + r * uy
        faced = ((incidence_deg(panes, ex, ey, ux, uy) <= cone_deg + CONE_MARGIN_DEG)
                 & (r <= evidence_range))
        x = np.floor((ex - origin[0]) / resolution).astype(int)
        y = np.floor((ey - origin[1]) / resolution).astype(int)
        inside = (x >= 0) & (y >= 0) & (x < shape[1]) & (y < shape[0])
        np.add.at(every, (y[inside], x[inside]), 1)
        np.add.at(face_on, (y[inside & faced], x[inside & faced]), 1)
    return every, face_on


def count_run(directory, mapper, evidence_range):
    """[cells, drawn glass] per bucket of face-on echoes of one simulated run, how many cells
    without a face-on echo other glass echoes reached, and of the cells faced 10 times or more
    not drawn glass, how many are drawn each of MISSED (the first class found within one cell, in
    that order; free also counts unknown)."""
    map_dir = os.path.join(directory, mapper)
    classes = read_pgm_grid(os.path.join(map_dir, "classes.pgm"))
    truth = read_pgm_grid(os.path.join(map_dir, "truth_cells.pgm"))
    if truth.shape != classes.shape:
        raise SystemExit("%s: truth_cells.pgm is not classes.pgm's size" % map_dir)
    origin, resolution = read_map_geometry(map_dir)
    with open(os.path.join(directory, "scene.yaml")) as scene_file:
        scene = yaml.safe_load(scene_file)
    cone_deg = scene.get("physics", {}).get("return_cone_deg")
    if cone_deg is None:  # the ideal beam model of the shipped scenes has no cone to face
        raise SystemExit("%s/scene.yaml: no physics.return_cone_deg (a procedural scene's)"
                         % directory)
    every, face_on = glass_echoes(os.path.join(directory, "sim.bag"), glass_panes(scene),
                                  float(cone_deg), evidence_range, classes.shape, origin,
                                  resolution)
    every, face_on = sum_within_one(every), sum_within_one(face_on)
    counted = (truth == GLASS_BIT) & within_one(classes != UNKNOWN)
    drawn = within_one(classes == GLASS)
    bucket = np.where(face_on == 0, 0, np.where(face_on < 10, 1, 2))
    counts = [[int(np.sum(counted & (bucket == b))), int(np.sum(counted & (bucket == b) & drawn))]
              for b in range(len(BUCKETS))]
    other_echoes = int(np.sum(counted & (bucket == 0) & (every > 0)))
    left = counted & (bucket == 2) & ~drawn
    missed = []
    for code in (STATIC, METAL, MOTION):
        here = left & within_one(classes == code)
        missed.append(int(np.sum(here)))
        left &= ~here
    missed.append(int(np.sum(left)))
    return counts, other_echoes, missed


def evidence_range_of_defaults():
    """The mapper's evidence range at its defaults: active_region_radius of config/default.yaml."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "config", "default.yaml")
    with open(path) as defaults:
        return float(yaml.safe_load(defaults)["active_region_radius"])


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    mapper = sys.argv[2] if len(sys.argv) > 2 else "RFM"
    evidence_range = evidence_range_of_defaults()
    rows = {}
    for config, seed, setup, split in read_manifest(out):
        if config != mapper:
            continue
        row = rows.setdefault((setup, split), {"seeds": 0, "counts": [[0, 0] for _ in BUCKETS],
                                               "other": 0, "missed": [0] * len(MISSED)})
        row["seeds"] += 1
        counts, other_echoes, missed = count_run(os.path.join(out, setup, seed), mapper,
                                                 evidence_range)
        for b, (cells, drawn) in enumerate(counts):
            row["counts"][b][0] += cells
            row["counts"][b][1] += drawn
        row["other"] += other_echoes
        row["missed"] = [a + b for a, b in zip(row["missed"], missed)]
    print("| setup | seeds | true glass cells | by the face-on echoes within %g m, within a cell "
          "(%%): %s | of those with none, reached by other glass echoes (%%) | drawn glass "
          "(recall, %%): all / %s | faced 10 times or more, not drawn glass, drawn (%%): %s |" % (
              evidence_range, " / ".join(BUCKETS), " / ".join(BUCKETS), " / ".join(MISSED)))
    print("|---|---|---:|---|---:|---|---|")
    for (setup, split), row in sorted(rows.items()):
        counts = row["counts"]
        total = sum(c[0] for c in counts)
        shares = " / ".join("%.1f" % (100.0 * c[0] / max(total, 1)) for c in counts)
        recall = " / ".join("%.1f" % (100.0 * c[1] / c[0]) if c[0] else "-" for c in counts)
        other = "%.1f" % (100.0 * row["other"] / counts[0][0]) if counts[0][0] else "-"
        missed = " / ".join("%.1f" % (100.0 * m / max(sum(row["missed"]), 1))
                            for m in row["missed"])
        print("| %s | %s (%d) | %d | %s | %s | %.1f / %s | %s |" % (
            setup, split, row["seeds"], total, shares, other,
            100.0 * sum(c[1] for c in counts) / max(total, 1), recall, missed))


if __name__ == "__main__":
    main()
