#!/usr/bin/env python3
"""Agreement of two map_server maps (PGM + YAML) on the cells both observed: the share of cells,
known (free or occupied) in both, that both call the same. Prints one JSON object.

  compare_maps.py A.yaml B.yaml
"""
import json
import os
import sys

import yaml

FREE, OCCUPIED, UNKNOWN = 254, 0, 205


def read_map(yaml_path):
    with open(yaml_path) as f:
        meta = yaml.safe_load(f)
    image = os.path.join(os.path.dirname(yaml_path), meta["image"])
    with open(image, "rb") as f:
        data = f.read()
    fields, at = [], 0
    while len(fields) < 4:  # magic, width, height, maxval, skipping comments
        while data[at:at + 1].isspace():
            at += 1
        if data[at:at + 1] == b"#":
            at = data.index(b"\n", at) + 1
            continue
        end = at
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[at:end])
        at = end
    if fields[0] != b"P5":
        sys.exit("compare_maps.py: %s is not a binary PGM" % image)
    width, height = int(fields[1]), int(fields[2])
    pixels = data[at + 1:at + 1 + width * height]
    return {"width": width, "height": height, "resolution": float(meta["resolution"]),
            "origin": meta["origin"], "pixels": pixels}


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    a, b = read_map(sys.argv[1]), read_map(sys.argv[2])
    if abs(a["resolution"] - b["resolution"]) > 1e-9:
        sys.exit("compare_maps.py: resolutions differ")
    r = a["resolution"]
    # Column/row of B's cell (0, 0) in A's grid (PGM rows run from the top: the highest y).
    shift_x = int(round((b["origin"][0] - a["origin"][0]) / r))
    shift_y = int(round((b["origin"][1] - a["origin"][1]) / r))
    both = agree = only_a = only_b = 0
    disagreements = {"a_free_b_occupied": 0, "a_occupied_b_free": 0}
    known_b = 0
    for by in range(b["height"]):
        y = by + shift_y  # in A, counting from the bottom
        row_b = (b["height"] - 1 - by) * b["width"]
        inside_y = 0 <= y < a["height"]
        row_a = (a["height"] - 1 - y) * a["width"] if inside_y else 0
        for bx in range(b["width"]):
            pb = b["pixels"][row_b + bx]
            x = bx + shift_x
            pa = a["pixels"][row_a + x] if inside_y and 0 <= x < a["width"] else UNKNOWN
            known_a_cell, known_b_cell = pa != UNKNOWN, pb != UNKNOWN
            known_b += known_b_cell
            if known_a_cell and known_b_cell:
                both += 1
                if (pa == OCCUPIED) == (pb == OCCUPIED):
                    agree += 1
                elif pa == OCCUPIED:
                    disagreements["a_occupied_b_free"] += 1
                else:
                    disagreements["a_free_b_occupied"] += 1
            elif known_b_cell:
                only_b += 1
    known_a = sum(1 for p in a["pixels"] if p != UNKNOWN)
    only_a = known_a - both
    print(json.dumps({"observed_in_both": both, "agreeing": agree,
                      "agreement_percent": 100.0 * agree / both if both else 0.0,
                      "observed_only_in_a": only_a, "observed_only_in_b": only_b,
                      **disagreements}))


if __name__ == "__main__":
    main()
