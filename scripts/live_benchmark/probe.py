#!/usr/bin/env python3
"""Watches one live-benchmark replay through rfm_node and writes what it measured as JSON.

  probe.py --pid NODE_PID --topics /scan_front,/scan_rear --out result.json

Until interrupted (SIGINT or SIGTERM) it records, for every scan topic:
  - the wall time each raw scan arrives here and the wall time its filtered scan
    (/rfm/<leaf>/filtered, same header) arrives: their difference is the node's own work on the
    scan (both messages cross the same local transport, so the transport cancels);
  - the simulated clock when the filtered scan arrives, less the scan's stamp: what a consumer on
    that clock sees (the sweep, the wait for TF and the node's work);
and samples the node's CPU time (/proc/PID/stat) and peak resident memory (VmHWM), and keeps the
last /rfm/stats (scans processed and dropped, map messages and their cells, publishing time).
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
from sensor_msgs.msg import LaserScan

CLOCK_TICKS = os.sysconf("SC_CLK_TCK")


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


def percentile(values, share):
    if not values:
        return None
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(share * len(ordered)))]


def summary_ms(values):
    return {"count": len(values), "median": percentile(values, 0.5),
            "p99": percentile(values, 0.99), "max": max(values) if values else None}


class Probe:
    def __init__(self, topics):
        self.lock = threading.Lock()
        self.raw_arrival = {}  # (topic, stamp) -> wall s
        self.node_ms = []
        self.stamp_ms = []
        self.filtered = 0
        self.stats = None
        self.counts = {}  # from /diagnostics, on wall time: current after the replay's clock stops
        self.first_scan_wall = None
        self.last_filtered_wall = None
        self.subscribers = []
        for topic in topics:
            leaf = topic.rstrip("/").rsplit("/", 1)[-1]
            self.subscribers.append(rospy.Subscriber(
                topic, LaserScan, self.on_raw, callback_args=topic, queue_size=1000,
                tcp_nodelay=True))
            self.subscribers.append(rospy.Subscriber(
                "/rfm/%s/filtered" % leaf, LaserScan, self.on_filtered, callback_args=topic,
                queue_size=1000, tcp_nodelay=True))
        self.subscribers.append(rospy.Subscriber("/rfm/stats", RfmStats, self.on_stats))
        self.subscribers.append(
            rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics))

    def on_raw(self, msg, topic):
        now = time.time()
        with self.lock:
            self.raw_arrival[(topic, msg.header.stamp.to_nsec())] = now
            if self.first_scan_wall is None:
                self.first_scan_wall = now

    def on_filtered(self, msg, topic):
        now = time.time()
        sim_now = rospy.get_time()
        with self.lock:
            self.filtered += 1
            self.last_filtered_wall = now
            arrived = self.raw_arrival.pop((topic, msg.header.stamp.to_nsec()), None)
            if arrived is not None:
                self.node_ms.append(1000.0 * (now - arrived))
            self.stamp_ms.append(1000.0 * (sim_now - msg.header.stamp.to_sec()))

    def on_stats(self, msg):
        with self.lock:
            self.stats = msg

    def on_diagnostics(self, msg):
        keys = {"Scans processed": "processed", "Scans dropped (total)": "dropped",
                "Scans lost in subscriber queues (total)": "lost"}
        with self.lock:
            for status in msg.status:
                for entry in status.values:
                    if entry.key in keys:
                        self.counts[keys[entry.key]] = int(float(entry.value))

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

    # The node's CPU time when the first scan arrived and when the last filtered scan did.
    cpu_at_first_scan, cpu_at_last_filtered, seen_filtered = None, None, 0
    while not stop["now"]:
        try:
            cpu = cpu_seconds(args.pid)
        except OSError:
            break  # the node is gone
        with probe.lock:
            started = probe.first_scan_wall is not None
            filtered = probe.filtered
        if started and cpu_at_first_scan is None:
            cpu_at_first_scan = cpu
        if filtered != seen_filtered:
            cpu_at_last_filtered, seen_filtered = cpu, filtered
        if args.expect and probe.accounted() >= args.expect:
            break
        time.sleep(0.05)  # polling the stop flag and the first scan

    with probe.lock:
        wall = (probe.last_filtered_wall or time.time()) - (probe.first_scan_wall or time.time())
        cpu_used = None
        if cpu_at_first_scan is not None and cpu_at_last_filtered is not None:
            cpu_used = cpu_at_last_filtered - cpu_at_first_scan
        try:
            peak = peak_rss_kb(args.pid)
        except OSError:
            peak = None
        stats = probe.stats
        result = {
            "filtered_scans": probe.filtered,
            "node_work_ms": summary_ms(probe.node_ms),
            "stamp_to_filtered_ms": summary_ms(probe.stamp_ms),
            "wall_s": wall,
            "cpu_share_of_one_core": (cpu_used / wall) if cpu_used is not None and wall > 0 else None,
            "peak_rss_kb": peak,
        }
        result.update({"scans_processed": probe.counts.get("processed"),
                       "scans_dropped": probe.counts.get("dropped", 0) + probe.counts.get("lost", 0)})
        if stats is not None:
            result.update({
                "full_maps_published": stats.full_maps_published,
                "map_updates_published": stats.map_updates_published,
                "map_cells_published": stats.map_cells_published,
                "map_publish_ms_total": stats.map_publish_ms_total,
                "motion_removal_ms_last": stats.motion_removal_ms,
            })
    with open(args.out, "w") as out:
        json.dump(result, out, indent=1)


if __name__ == "__main__":
    main()
