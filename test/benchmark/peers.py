"""Driver of run_peers.sh: runs each mapper on each recording ROUNDS times, one after the other,
and prints the medians as a markdown table."""
import json
import os

import rosbag
import statistics
import subprocess
import sys

RECORDINGS = ["freiburg-079", "freiburg-campus", "atrium"]
MAPPERS = ["RFM (all stages)", "plain grid", "OctoMap (planar slice)", "MRPT 2D grid"]
PEER_BINARIES = {MAPPERS[2]: "rfm_octomap_peer", MAPPERS[3]: "rfm_mrpt_peer"}


def run(command):
    """Runs command; returns its stdout and its peak resident memory in MB."""
    with open(os.devnull, "w") as devnull:
        process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=devnull, text=True)
        output = process.stdout.read()
        _, status, usage = os.wait4(process.pid, 0)
    if status != 0:
        raise RuntimeError("%s failed (status %d)" % (" ".join(command), status))
    return output, usage.ru_maxrss / 1024.0


def offline(binaries, out, bag, topics, baseline):
    directory = os.path.join(out, "run")
    command = [os.path.join(binaries, "rfm_offline"), "--bag", bag, "--out", directory,
               "--scan-topics", topics] + (["--baseline"] if baseline else [])
    _, peak_mb = run(command)
    with open(os.path.join(directory, "summary.json")) as f:
        summary = json.load(f)
    return summary["scans"]["total"], summary["timing"]["stages_s"]["process"], peak_mb


def peer(binary, bag, topics):
    """A peer program (rfm_octomap_peer, rfm_mrpt_peer): its JSON line's scans and seconds."""
    output, peak_mb = run([binary, bag, topics])
    result = json.loads(output)
    return result["scans"], result["process_seconds"], peak_mb


def scan_topics(bag):
    """The bag's LaserScan topics, comma-separated."""
    with rosbag.Bag(bag) as b:
        topics = b.get_type_and_topic_info().topics
    return ",".join(sorted(t for t, info in topics.items()
                           if info.msg_type == "sensor_msgs/LaserScan"))


def main():
    out, rounds, binaries = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    mappers = [m for m in MAPPERS
               if m not in PEER_BINARIES or os.path.exists(os.path.join(binaries, PEER_BINARIES[m]))]
    for missing in sorted(set(MAPPERS) - set(mappers)):
        print("%s left out: %s is not built" % (missing, PEER_BINARIES[missing]), file=sys.stderr)
    samples = {}  # (recording, mapper) -> [(scans per s, peak MB)]
    for _ in range(rounds):
        for name in RECORDINGS:
            bag = os.path.join(out, name + ".bag")
            topics = scan_topics(bag)
            for mapper in mappers:
                if mapper in PEER_BINARIES:
                    scans, seconds, peak = peer(os.path.join(binaries, PEER_BINARIES[mapper]),
                                                bag, topics)
                else:
                    scans, seconds, peak = offline(binaries, out, bag, topics,
                                                   mapper == MAPPERS[1])
                samples.setdefault((name, mapper), []).append((scans / seconds, peak, scans))
                print("%s, %s: %d scans, %.2f s, %.0f MB" % (name, mapper, scans, seconds, peak),
                      file=sys.stderr)
    print("| recording | mapper | scans | scans per s (median of %d) | speed vs the RFM (median of per-round ratios) | peak RSS MB |"
          % rounds)
    print("|---|---|---:|---:|---:|---:|")
    for name in RECORDINGS:
        rfm_rows = samples[(name, MAPPERS[0])]
        for mapper in mappers:
            rows = samples[(name, mapper)]
            # The ratio round by round (runs side by side), then its median.
            ratio = statistics.median(row[0] / rfm[0] for row, rfm in zip(rows, rfm_rows))
            print("| %s | %s | %d | %.0f | %.2fx | %.0f |" % (
                name, mapper, rows[0][2], statistics.median(row[0] for row in rows), ratio,
                statistics.median(row[1] for row in rows)))


if __name__ == "__main__":
    main()
