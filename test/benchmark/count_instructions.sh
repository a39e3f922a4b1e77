#!/usr/bin/env bash
# Instructions executed by two builds of rfm_benchmark, benchmark by benchmark, under
# valgrind's callgrind: a count that does not move with the machine's load, where timings on a
# shared machine swing by 5-10 %. Each benchmark runs in a process of its own, its setup and one
# iteration (--benchmark_min_time=0), the same work in both builds.
#
#   test/benchmark/count_instructions.sh A/rfm_benchmark B/rfm_benchmark [BENCHMARK...]
#
# Prints one line a benchmark: instructions of A, of B, and B/A. The default benchmarks are the
# single-thread ones; with two threads a helper's spinning adds a varying count (the runs of one
# build differ by a few per mille, which the script also shows: A is counted twice).
# Environment: JOBS processes at once (default 2). Needs valgrind.
set -euo pipefail

if (($# < 2)); then
  sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
a="$1" b="$2"
shift 2
benchmarks=("$@")
if ((${#benchmarks[@]} == 0)); then
  benchmarks=(BM_RfmInsert/1 BM_RfmSweepOnly BM_PlainGridInsert BM_RfmOverPlainPaired/iterations:60
    BM_MotionRemoval/1 BM_MotionRemoval/0 BM_MotionClassify/1 BM_MotionClassify/0
    BM_WholeUpdatePerScan)
fi
command -v valgrind > /dev/null || {
  echo "count_instructions.sh: valgrind not found (apt-get install valgrind)" >&2
  exit 1
}
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

# Instructions of one benchmark in one build: callgrind's "Collected" total for the process.
count() {
  local binary="$1" benchmark="$2" tag="$3"
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$binary" \
    --benchmark_filter="^${benchmark}\$" --benchmark_min_time=0 > /dev/null 2> "$scratch/$tag.err"
  sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$scratch/$tag.err" > "$scratch/$tag"
  if [[ ! -s "$scratch/$tag" ]]; then
    echo "count_instructions.sh: no count for $benchmark in $binary:" >&2
    tail -5 "$scratch/$tag.err" >&2
    return 1
  fi
}
export -f count
export scratch

runs=()
for i in "${!benchmarks[@]}"; do
  runs+=("$a ${benchmarks[$i]} a$i" "$a ${benchmarks[$i]} a2_$i" "$b ${benchmarks[$i]} b$i")
done
printf '%s\n' "${runs[@]}" | xargs -P "${JOBS:-2}" -L 1 bash -c 'count "$0" "$1" "$2"'

printf '%-40s %15s %15s %8s %8s\n' benchmark A B B/A A/A
for i in "${!benchmarks[@]}"; do
  read -r ia < "$scratch/a$i"
  read -r ia2 < "$scratch/a2_$i"
  read -r ib < "$scratch/b$i"
  awk -v n="${benchmarks[$i]}" -v a="$ia" -v a2="$ia2" -v b="$ib" \
    'BEGIN { printf "%-40s %15.0f %15.0f %8.4f %8.4f\n", n, a, b, b / a, a2 / a }'
done
