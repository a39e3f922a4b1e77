"""Draws BM_Scaling's medians (rfm_benchmark JSON) as doc/scaling.png: time and active-region
memory per scan against the radius, the theta bins and the beams, each with the others at their
defaults, beside the line through the default proportional to the parameter (linear)."""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

DEFAULTS = {"radius_m": 10, "theta_bins": 180, "beams": 1081}
AXES = [("radius_m", "active-region radius (m)"), ("theta_bins", "theta bins"),
        ("beams", "beams per scan")]


def medians(path):
    with open(path) as f:
        runs = json.load(f)["benchmarks"]
    rows = []
    for run in runs:
        if run.get("aggregate_name") != "median":
            continue
        rows.append({"ms": run["real_time"], "MB": run["active_region_MB"],
                     **{key: int(round(run[key])) for key in DEFAULTS}})
    return rows


def main():
    rows = medians(sys.argv[1])
    fig, panels = plt.subplots(2, 3, figsize=(12, 6.5))
    for column, (key, label) in enumerate(AXES):
        others = [k for k in DEFAULTS if k != key]
        points = sorted((r[key], r["ms"], r["MB"]) for r in rows
                        if all(r[k] == DEFAULTS[k] for k in others))
        xs = [p[0] for p in points]
        base = next(p for p in points if p[0] == DEFAULTS[key])
        for row, (index, unit) in enumerate([(1, "ms per scan"), (2, "active region MB")]):
            ax = panels[row][column]
            ax.plot(xs, [p[index] for p in points], "o-", label="measured (median of 5)")
            ax.plot(xs, [base[index] * x / DEFAULTS[key] for x in xs], "--", color="grey",
                    label="linear through the default")
            if key == "radius_m" and row == 1:
                ax.plot(xs, [base[index] * (x / DEFAULTS[key]) ** 2 for x in xs], ":",
                        color="grey", label="quadratic through the default")
            ax.set_xscale("log", base=2)
            ax.set_yscale("log", base=2)
            ax.set_xticks(xs)
            ax.set_xticklabels([str(x) for x in xs])
            ax.set_xlabel(label)
            ax.set_ylabel(unit)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
    fig.suptitle("rfm_benchmark BM_Scaling: whole online update per scan and active-region "
                 "memory (defaults 10 m, 180 bins, 1081 beams)", fontsize=10)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=90)


if __name__ == "__main__":
    main()
