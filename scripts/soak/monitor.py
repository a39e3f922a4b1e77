#!/usr/bin/env python3
"""Samples a running rfm_node for the soak test: every PERIOD s of wall time, one CSV line with
its resident memory (/proc/PID/status VmRSS) and what its /diagnostics report (scans processed and
dropped, field, archive and explored map bytes). Diagnostics run on wall time, so they keep coming
when a replay's simulated clock has stopped.

  monitor.py --pid PID --out samples.csv [--period 10]

Runs until interrupted (SIGINT or SIGTERM).
"""
import argparse
import signal
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray

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
    latest = {}
    keys = {"Scans processed": "scans_processed", "Scans dropped (total)": "dropped",
            "Scans lost in subscriber queues (total)": "lost",
            "Field memory (bytes)": "field_bytes", "Archived memory (bytes)": "archived_bytes",
            "Explored map memory (bytes)": "explored_map_bytes"}

    def on_diagnostics(msg):
        for status in msg.status:
            for kv in status.values:
                if kv.key in keys:
                    latest[keys[kv.key]] = int(float(kv.value))

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
            if len(latest) == len(keys):
                out.write("%.1f,%.3f,%d,%d,%d,%d,%d,%d\n" % (
                    time.time() - start, rospy.get_time(), rss, latest["scans_processed"],
                    latest["dropped"] + latest["lost"], latest["field_bytes"],
                    latest["archived_bytes"], latest["explored_map_bytes"]))
                out.flush()
            deadline = time.time() + args.period
            while not stop["now"] and time.time() < deadline:
                time.sleep(0.2)  # polling the stop flag between samples


if __name__ == "__main__":
    main()
