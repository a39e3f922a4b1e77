#!/usr/bin/env python3
"""The soak's verdict from what soak.sh left in OUT: memory growth after warm-up besides the
explored map, scans dropped and processed, and the two maps' agreement. Writes
OUT/soak_report.json, prints it with PASS/FAIL per target, and exits 1 if a target is missed.

  report.py OUT COMPOSED.json SCANS [WARMUP_LAPS]

Warm-up is the first WARMUP_LAPS laps (default 2): the first explores every scene, the second is
the first revisit, in which the archive of evidence reaches its working set (restoring and
re-archiving tiles); memory is judged from there to the end of the replay.
"""
import csv
import json
import sys


def main():
    out, summary_path, scans = sys.argv[1], sys.argv[2], int(sys.argv[3])
    warmup_laps = int(sys.argv[4]) if len(sys.argv) > 4 else 2
    summary = json.load(open(summary_path))
    rows = [{k: float(v) for k, v in row.items()}
            for row in csv.DictReader(open(out + "/samples_replay.csv"))]
    lap_s = summary["duration_s"] / summary["laps"]

    def at(laps):
        t = summary["start_s"] + laps * lap_s
        return next((r for r in rows if r["ros_time_s"] >= t), rows[-1])

    warm, end = at(warmup_laps), rows[-1]
    explored_kb = (end["explored_map_bytes"] - warm["explored_map_bytes"]) / 1024.0
    growth = 100.0 * (end["rss_kb"] - warm["rss_kb"] - explored_kb) / warm["rss_kb"]
    after_first = at(1)
    growth_after_first = 100.0 * (
        end["rss_kb"] - after_first["rss_kb"]
        - (end["explored_map_bytes"] - after_first["explored_map_bytes"]) / 1024.0
    ) / after_first["rss_kb"]
    after_warm = [r["rss_kb"] for r in rows if r["ros_time_s"] >= warm["ros_time_s"]]
    agreement = json.load(open(out + "/agreement.json"))
    dropped, processed = int(end["scans_dropped"]), int(end["scans_processed"])
    report = {
        "recording_s": summary["duration_s"], "laps": summary["laps"], "lap_s": lap_s,
        "warm_up_laps": warmup_laps, "scans_in_bag": scans, "scans_processed": processed,
        "scans_dropped": dropped,
        "rss_kb_after_first_lap": after_first["rss_kb"], "rss_kb_at_warm_up": warm["rss_kb"],
        "rss_kb_at_end": end["rss_kb"], "rss_kb_min_after_warm_up": min(after_warm),
        "rss_kb_max_after_warm_up": max(after_warm),
        "explored_map_kb_at_end": end["explored_map_bytes"] / 1024.0,
        "explored_map_kb_growth": explored_kb,
        "archived_kb_at_warm_up": warm["archived_bytes"] / 1024.0,
        "archived_kb_at_end": end["archived_bytes"] / 1024.0,
        "memory_growth_percent_besides_map": growth,
        "memory_growth_percent_after_first_lap": growth_after_first,
        "map_agreement_percent": agreement["agreement_percent"], "agreement": agreement,
    }
    checks = {"memory growth < 5 %": growth < 5.0, "no scan dropped": dropped == 0,
              "all scans processed": processed == scans,
              "map agreement >= 99 %": agreement["agreement_percent"] >= 99.0}
    report["checks"] = checks
    json.dump(report, open(out + "/soak_report.json", "w"), indent=2)
    print(json.dumps(report, indent=2))
    for name, ok in checks.items():
        print(("PASS " if ok else "FAIL ") + name)
    sys.exit(0 if all(checks.values()) else 1)


if __name__ == "__main__":
    main()
