#!/usr/bin/env python3
"""Times two builds side by side: A B A B ..., the ratio B/A taken pair by pair.

Pairing keeps a ratio meaningful while a shared machine's speed drifts; the median of the
per-pair ratios is the figure to quote, min and max show the noise.

Whole processes (wall seconds and peak RSS of each run):
    side_by_side.py --rounds 7 --a 'CMD_A ...' --b 'CMD_B ...'
Google Benchmark binaries (each benchmark's median real time within a run; the pairs are taken
benchmark by benchmark, so that the two runs of a pair are seconds apart):
    side_by_side.py --rounds 11 --gbench --a BIN_A --b BIN_B -- --benchmark_filter=Insert

A binary under a catkin workspace's devel/lib runs with that workspace's libraries first on
LD_LIBRARY_PATH, so each build uses its own librfm_core.so.
"""
import argparse
import json
import os
import re
import shlex
import statistics
import subprocess
import sys
import time


def environment_for(command):
    """The environment of a command whose program lies under some devel/lib."""
    env = dict(os.environ)
    program = os.path.realpath(command[0])
    marker = os.sep + os.path.join("devel", "lib") + os.sep
    if marker in program:
        lib = program[: program.index(marker) + len(marker) - 1]
        env["LD_LIBRARY_PATH"] = lib + os.pathsep + env.get("LD_LIBRARY_PATH", "")
    return env


def run_whole(command):
    """Wall seconds and peak RSS (MB) of one run of the command."""
    start = time.monotonic()
    process = subprocess.Popen(command, env=environment_for(command), stdin=subprocess.DEVNULL,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.monotonic() - start
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"side_by_side: {shlex.join(command)} exited with status {status}")
    return {"wall s": wall, "peak RSS MB": usage.ru_maxrss / 1024.0}


def run_gbench(command):
    """Each benchmark's median real time (ms) in one run of a Google Benchmark binary."""
    output = subprocess.run(command + ["--benchmark_format=json"], env=environment_for(command),
                            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL, check=True, text=True).stdout
    times = {}
    for entry in json.loads(output)["benchmarks"]:
        if entry.get("aggregate_name", "median") != "median":
            continue
        scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[entry.get("time_unit", "ns")]
        times[entry.get("run_name", entry["name"]) + " ms"] = entry["real_time"] * scale
    return times


def benchmark_names(command):
    """The benchmarks a Google Benchmark command would run."""
    output = subprocess.run(command + ["--benchmark_list_tests=true"], env=environment_for(command),
                            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL, check=True, text=True).stdout
    return [line.strip() for line in output.splitlines() if line.strip()]


def without_filter(command):
    return [arg for arg in command if not arg.startswith("--benchmark_filter=")]


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--a", required=True, help="command A (the baseline)")
    parser.add_argument("--b", required=True, help="command B")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--gbench", action="store_true", help="A and B are Google Benchmark binaries")
    parser.add_argument("extra", nargs="*", help="arguments given to both (after --)")
    args = parser.parse_args()
    if args.rounds < 1:
        parser.error("--rounds must be at least 1")

    commands = {name: shlex.split(text) + args.extra for name, text in (("A", args.a), ("B", args.b))}
    rounds = [{"A": {}, "B": {}} for _ in range(args.rounds)]
    if args.gbench:
        for benchmark in benchmark_names(commands["A"]):
            exact = "--benchmark_filter=^" + re.escape(benchmark) + "$"
            for r in rounds:
                for name, command in commands.items():
                    r[name].update(run_gbench(without_filter(command) + [exact]))
            print(f"{benchmark}: {args.rounds} pairs done", file=sys.stderr, flush=True)
    else:
        for index, r in enumerate(rounds):
            for name, command in commands.items():
                r[name].update(run_whole(command))
            print(f"round {index + 1} of {args.rounds} done", file=sys.stderr, flush=True)

    print("| measure | A median | B median | B/A per pair: min / median / max |")
    print("|---|---:|---:|---|")
    for measure in rounds[0]["A"]:
        if not all(measure in r["A"] and measure in r["B"] for r in rounds):
            continue
        a = [r["A"][measure] for r in rounds]
        b = [r["B"][measure] for r in rounds]
        ratios = [y / x for x, y in zip(a, b) if x > 0]
        if not ratios:
            continue
        print(f"| {measure} | {statistics.median(a):.4g} | {statistics.median(b):.4g} | "
              f"{min(ratios):.3f} / **{statistics.median(ratios):.3f}** / {max(ratios):.3f} |")


if __name__ == "__main__":
    main()
