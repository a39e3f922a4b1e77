#!/usr/bin/env python3
"""Samples a running rfm_node for the soak test: every PERIOD s of wall time, one CSV line with
its resident memory (/proc/PID/status VmRSS), /rfm/stats (scans processed and dropped, field and
archive bytes) and the explored map's memory from /diagnostics.

  monitor.py --pid PID --out samples.csv [--period 10]

Runs until interrupted (SIGINT or SIGTERM).
"""
import argparse
import signal
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray
from reflectance_field_map.msg import RfmStats

COLUMNS = ("wall_s", "ros_time_s", "rss_kb", "scans_processed", "scans_dropped", "field_bytes",
           "archived_bytes", "explored_map_bytes")


def rss_kb(pid):
    with open("/proc/%d/status" % pid) as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pid", type=int, required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--period", type=float, default=10.0)
    args = parser.parse_args(rospy.myargv()[1:])

    rospy.init_node("rfm_soak_monitor", disable_signals=True)
    latest = {"stats": None, "explored": 0}

    def on_stats(msg):
        latest["stats"] = msg

    def on_diagnostics(msg):
        for status in msg.status:
            for kv in status.values:
                if kv.key == "Explored map memory (bytes)":
                    latest["explored"] = int(kv.value)

    rospy.Subscriber("/rfm/stats", RfmStats, on_stats)
    rospy.Subscriber("/diagnostics", DiagnosticArray, on_diagnostics)
    stop = {"now": False}
    signal.signal(signal.SIGINT, lambda *_: stop.update(now=True))
    signal.signal(signal.SIGTERM, lambda *_: stop.update(now=True))
    start = time.time()
    with open(args.out, "w") as out:
        out.write(",".join(COLUMNS) + "\n")
        while not stop["now"]:
            try:
                rss = rss_kb(args.pid)
            except OSError:
                break  # the node is gone
            stats = latest["stats"]
            if stats is not None:
                out.write("%.1f,%.3f,%d,%d,%d,%d,%d,%d\n" % (
                    time.time() - start, rospy.get_time(), rss, stats.scans_processed,
                    stats.scans_dropped, stats.field_bytes, stats.archived_bytes,
                    latest["explored"]))
                out.flush()
            deadline = time.time() + args.period
            while not stop["now"] and time.time() < deadline:
                time.sleep(0.2)  # polling the stop flag between samples


if __name__ == "__main__":
    main()
