#!/usr/bin/env python3
"""Whose motion rays a map kept, and whether the recording ever showed those people gone.

Reads the output of scripts/run_random_evaluation.sh (OUT/SETUP/SEED/{sim.bag, scene.yaml,
MAPPER/labels.bag}) and sorts every true motion beam that each MAPPER labelled KEPT by the person it
hit (the nearest person of the scene file at the scan's stamp, within 0.7 m):
  - walking: the person was moving;
  - standing, stays: standing, and standing there until the recording ends;
  - standing, left unseen: left later, and no later beam crossed their footprint (within their
    radius of where they stood, on past its middle) while they were a metre or more away: the
    map was never shown the spot empty;
  - standing, left, seen: some later beam did (at least one: an upper bound on what a map could
    have removed), split by whether any of those beams returned from beyond the spot (seen by a
    return) or none did (seen without a return: beams beyond range, which the RFM takes for
    dropouts where they cross structure).

    scripts/kept_motion.py OUT [MAPPER ...]    # MAPPER: RFM (default), plain_grid

Prints one markdown table: a row per mapper, setup and seed split, shares of all true motion
beams. Each simulated bag is read once for all mappers.
Needs python3-rosbag, python3-numpy and python3-yaml.
"""
import math
import os
import sys

import numpy as np
import yaml

from sim_bag_io import NO_RETURN, read_labels, read_scans_in_map, scenes_mapped_by

MOTION = 4  # RayTruth.MOTION
KEPT = 1  # RayLabels.KEPT
NEAREST_PERSON = 0.7  # m
PERSON_GONE = 1.0  # m from the spot
STEP = 0.05  # s, as the simulator's crowd planner samples


class Person:
    """A person of the scene file, moved as rfm_sim moves them (src/sim/people.cpp)."""

    def __init__(self, spec):
        self.radius = spec["radius"]  # the footprint: body or legs
        self.start = spec.get("start_time", 0.0)
        self.end = spec.get("end_time", math.inf)
        self.loop = spec.get("loop", False)
        points = [(w[0], w[1], w[2] if len(w) > 2 else 0.0) for w in spec["waypoints"]]
        if self.loop:
            points.append(points[0])
        # (from, to, pause before walking, walking time)
        self.legs = [((a[0], a[1]), (b[0], b[1]), a[2], math.dist(a[:2], b[:2]) / spec["speed"])
                     for a, b in zip(points, points[1:])]
        if not self.loop:
            last = (points[-1][0], points[-1][1])
            self.legs.append((last, last, points[-1][2], 0.0))
        self.cycle = sum(pause + walk for _, _, pause, walk in self.legs)

    def at(self, t):
        """(position, standing) at time t, or None while absent."""
        if t < self.start or t > self.end:
            return None
        local = t - self.start
        if self.loop and self.cycle > 0.0:
            local = math.fmod(local, self.cycle)
        elif local > self.cycle:
            return None
        for a, b, pause, walk in self.legs:
            if local <= pause:
                return a, True
            local -= pause
            if local <= walk:
                f = local / walk if walk > 0.0 else 1.0
                return (a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])), False
            local -= walk
        return self.legs[-1][1], True

    def leaves(self, spot, t, duration):
        """When the person standing at spot at t is first elsewhere, or None."""
        s = t
        while s < duration:
            s += STEP
            here = self.at(s)
            if here is None or math.dist(here[0], spot) > STEP:
                return s
        return None


def seen_through(scans, person, spot, after, origin):
    """How a beam of a scan after `after` (scene time), with the person gone from the spot,
    crossed their footprint there (passed within their radius of it, and on past its middle):
    "left, seen by a return" if one such beam returned from beyond it, "left, seen without a
    return" if only beams without a return did, None if none did. Beams pass between a standing
    person's legs, hence only with the person gone."""
    seen = None
    for scan in scans:
        t = scan["stamp"] - origin
        if t <= after:
            continue
        where = person.at(t)
        if where is not None and math.dist(where[0], spot) < PERSON_GONE:
            continue
        vx, vy = spot[0] - scan["x"], spot[1] - scan["y"]
        along = vx * scan["cos"] + vy * scan["sin"]
        across = np.abs(vy * scan["cos"] - vx * scan["sin"])
        crossing = (along > 0.0) & (across < person.radius) & (scan["ranges"] > along)
        if not np.any(crossing):
            continue
        if np.any(scan["ranges"][crossing] < NO_RETURN):
            return "left, seen by a return"
        seen = "left, seen without a return"
    return seen


def classify_run(directory, mappers):
    """Counts per mapper of one simulated run."""
    scene = yaml.safe_load(open(os.path.join(directory, "scene.yaml")))
    people = [Person(spec) for spec in scene.get("people", [])]
    scans, origin = read_scans_in_map(os.path.join(directory, "sim.bag"))
    spots = {}  # (person, x, y) -> "stays", "left unseen" or "left, seen ...", for every map
    return {mapper: classify_labels(directory, mapper, scene["duration"], people, scans, origin,
                                    spots) for mapper in mappers}


def classify_labels(directory, mapper, duration, people, scans, origin, spots):
    labels = read_labels(os.path.join(directory, mapper, "labels.bag"))
    counts = {"motion": 0, "walking": 0, "stays": 0, "left unseen": 0,
              "left, seen without a return": 0, "left, seen by a return": 0, "nobody near": 0}
    for scan in scans:
        motion = np.nonzero(scan["truth"] == MOTION)[0]
        counts["motion"] += len(motion)
        label = labels.get(scan["key"])
        if label is None or len(label) != len(scan["truth"]):
            raise SystemExit("%s: no labels for a scan of %s" % (directory, scan["key"][0]))
        t = scan["stamp"] - origin
        present = [(i, p.at(t)) for i, p in enumerate(people)]
        present = [(i, where) for i, where in present if where is not None]
        for beam in motion[label[motion] == KEPT]:
            r = scan["ranges"][beam]
            hit = (scan["x"] + r * scan["cos"][beam], scan["y"] + r * scan["sin"][beam])
            near = [(math.dist(where[0], hit), i, where) for i, where in present]
            near = [n for n in near if n[0] < NEAREST_PERSON]
            if not near:
                counts["nobody near"] += 1
                continue
            _, i, (position, standing) = min(near)
            if not standing:
                counts["walking"] += 1
                continue
            spot = (i, round(position[0], 3), round(position[1], 3))
            if spot not in spots:
                left = people[i].leaves(position, t, duration)
                if left is None:
                    spots[spot] = "stays"
                else:
                    seen = seen_through(scans, people[i], position, left, origin)
                    spots[spot] = seen or "left unseen"
            counts[spots[spot]] += 1
    return counts


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    mappers = sys.argv[2:] or ["RFM"]
    rows = {}
    for (setup, seed), split in scenes_mapped_by(out, mappers).items():
        for mapper, counts in classify_run(os.path.join(out, setup, seed), mappers).items():
            total = rows.setdefault((mappers.index(mapper), setup, split), {"seeds": 0})
            total["seeds"] += 1
            for k, v in counts.items():
                total[k] = total.get(k, 0) + v
    columns = ["walking", "stays", "left unseen", "left, seen without a return",
               "left, seen by a return", "nobody near"]
    print("| setup | seeds | mapper | motion beams | removed (%) | kept, of all motion beams (%): "
          + " / ".join(columns) + " |")
    print("|---|---|---|---:|---:|---|")
    for (mapper_index, setup, split), c in sorted(rows.items()):
        kept = sum(c[k] for k in columns)
        share = " / ".join("%.1f" % (100.0 * c[k] / max(c["motion"], 1)) for k in columns)
        print("| %s | %s (%d) | %s | %d | %.1f | %s |" % (
            setup, split, c["seeds"], mappers[mapper_index], c["motion"],
            100.0 - 100.0 * kept / max(c["motion"], 1), share))


if __name__ == "__main__":
    main()
