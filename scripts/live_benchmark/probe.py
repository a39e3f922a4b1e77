#!/usr/bin/env python3
"""Watches one live-benchmark replay through rfm_node and writes what it measured as JSON.

  probe.py --pid NODE_PID --topics /scan_front,/scan_rear --expect SCANS --out result.json

It subscribes to the node's filtered scans (/rfm/<leaf>/filtered) as a consumer would, so the
node labels and publishes them, without decoding them (it only counts). The latencies are the
node's own (/diagnostics, on wall time, since its start): a scan's arrival at the node to its
filtered scan published (wall clock), ROS time at that moment less the scan's stamp, and a
motion-removal pass's start to its map update published (wall clock). It
samples the node's CPU time (/proc/PID/stat) and peak resident memory (VmHWM), and keeps the last
/rfm/stats (map messages, their cells and publishing time). It ends once the node has processed
or dropped --expect scans, or when interrupted (SIGINT or SIGTERM).
"""
import argparse
import json
import os
import signal
import threading
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray
from reflectance_field_map.msg import RfmStats

CLOCK_TICKS = os.sysconf("SC_CLK_TCK")
COUNTS = {"Scans processed": "processed", "Scans dropped (total)": "dropped",
          "Scans lost in subscriber queues (total)": "lost"}
LATENCIES = {"Scan latency median (ms)": ("arrival_to_filtered_ms", "median"),
             "Scan latency p99 (ms)": ("arrival_to_filtered_ms", "p99"),
             "Scan latency max (ms)": ("arrival_to_filtered_ms", "max"),
             "TF wait median (ms)": ("tf_wait_ms", "median"),
             "TF wait p99 (ms)": ("tf_wait_ms", "p99"),
             "TF wait max (ms)": ("tf_wait_ms", "max"),
             "Scan work median (ms)": ("own_work_ms", "median"),
             "Scan work p99 (ms)": ("own_work_ms", "p99"),
             "Scan work max (ms)": ("own_work_ms", "max"),
             "Scan age median (ms)": ("stamp_to_filtered_ms", "median"),
             "Scan age p99 (ms)": ("stamp_to_filtered_ms", "p99"),
             "Scan age max (ms)": ("stamp_to_filtered_ms", "max"),
             "Pass to map update median (ms)": ("pass_to_update_ms", "median"),
             "Pass to map update p99 (ms)": ("pass_to_update_ms", "p99"),
             "Pass to map update max (ms)": ("pass_to_update_ms", "max")}


def cpu_seconds(pid):
    with open("/proc/%d/stat" % pid) as stat:
        fields = stat.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS  # utime + stime


def peak_rss_kb(pid):
    with open("/proc/%d/status" % pid) as status:
        for line in status:
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
    return 0


class Probe:
    def __init__(self, topics):
        self.lock = threading.Lock()
        self.filtered = 0
        self.first_wall = None
        self.last_wall = None
        self.stats = None
        self.counts = {}
        self.latency = {group: {} for group, _ in LATENCIES.values()}
        self.subscribers = [
            rospy.Subscriber("/rfm/%s/filtered" % topic.rstrip("/").rsplit("/", 1)[-1],
                             rospy.AnyMsg, self.on_filtered, queue_size=1000, tcp_nodelay=True)
            for topic in topics]
        self.subscribers.append(rospy.Subscriber("/rfm/stats", RfmStats, self.on_stats))
        self.subscribers.append(
            rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics))

    def on_filtered(self, _):
        now = time.time()
        with self.lock:
            self.filtered += 1
            self.last_wall = now
            if self.first_wall is None:
                self.first_wall = now

    def on_stats(self, msg):
        with self.lock:
            self.stats = msg

    def on_diagnostics(self, msg):
        with self.lock:
            for status in msg.status:
                for entry in status.values:
                    if entry.key in COUNTS:
                        self.counts[COUNTS[entry.key]] = int(float(entry.value))
                    elif entry.key in LATENCIES:
                        group, name = LATENCIES[entry.key]
                        self.latency[group][name] = float(entry.value)

    def accounted(self):
        with self.lock:
            return sum(self.counts.values())


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pid", type=int, required=True)
    parser.add_argument("--topics", required=True, help="comma-separated scan topics")
    parser.add_argument("--out", required=True)
    parser.add_argument("--expect", type=int, default=0,
                        help="scans in the replay: stop once the node has processed or dropped "
                             "them all")
    args = parser.parse_args(rospy.myargv()[1:])

    rospy.init_node("rfm_live_benchmark_probe", disable_signals=True)
    probe = Probe([topic for topic in args.topics.split(",") if topic])
    stop = {"now": False}
    signal.signal(signal.SIGINT, lambda *_: stop.update(now=True))
    signal.signal(signal.SIGTERM, lambda *_: stop.update(now=True))
    open(args.out + ".ready", "w").close()  # the subscriptions exist: the replay may start

    # The node's CPU time when the first filtered scan came and when the last one did.
    cpu_first, cpu_last, seen = None, None, 0
    while not stop["now"]:
        try:
            cpu = cpu_seconds(args.pid)
        except OSError:
            break  # the node is gone
        with probe.lock:
            filtered = probe.filtered
        if filtered and cpu_first is None:
            cpu_first = cpu
        if filtered != seen:
            cpu_last, seen = cpu, filtered
        if args.expect and probe.accounted() >= args.expect:
            time.sleep(1.5)  # one more diagnostics message: the latencies of the last scans
            break
        time.sleep(0.05)  # polling the stop flag and the node's CPU time

    with probe.lock:
        wall = (probe.last_wall or 0.0) - (probe.first_wall or 0.0)
        cpu_used = cpu_last - cpu_first if cpu_first is not None and cpu_last is not None else None
        try:
            peak = peak_rss_kb(args.pid)
        except OSError:
            peak = None
        result = {
            "filtered_scans": probe.filtered,
            "wall_s": wall,
            "cpu_share_of_one_core": (cpu_used / wall) if cpu_used is not None and wall > 0 else None,
            "peak_rss_kb": peak,
            "scans_processed": probe.counts.get("processed"),
            "scans_dropped": probe.counts.get("dropped", 0) + probe.counts.get("lost", 0),
            "scans_played": args.expect,
        }
        # Scans the node never saw: dropped from a full subscriber queue, which the node counts
        # only when the publisher numbers its messages (header.seq).
        result["scans_never_seen"] = max(
            0, args.expect - (result["scans_processed"] or 0) - result["scans_dropped"])
        result.update(probe.latency)
        stats = probe.stats
        if stats is not None:
            result.update({
                "full_maps_published": stats.full_maps_published,
                "map_updates_published": stats.map_updates_published,
                "map_cells_published": stats.map_cells_published,
                "map_publish_ms_total": stats.map_publish_ms_total,
            })
    with open(args.out, "w") as out:
        json.dump(result, out, indent=1)


if __name__ == "__main__":
    main()
