#!/usr/bin/env bash
# Builds the libFuzzer targets of test/fuzz with clang (apart from catkin, in $RFM_FUZZ_BUILD,
# by default rfm_fuzz_build beside the catkin workspace) and runs each for RFM_FUZZ_SECONDS
# (default 30) from its committed corpus. Needs a built workspace ($RFM_WS, scripts/build.sh)
# for the package's generated message headers. Exits non-zero when a target crashes, leaks,
# times out or runs out of memory; the input that did it is kept under $RFM_FUZZ_BUILD/findings.
#   RFM_FUZZ_TARGETS="scene laser_scan"  runs only those targets
#   RFM_FUZZ_BUILD_ONLY=1                builds and stops
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/workspace.sh"
build_dir="${RFM_FUZZ_BUILD:-$(dirname "$rfm_ws")/rfm_fuzz_build}"
seconds="${RFM_FUZZ_SECONDS:-30}"
targets="${RFM_FUZZ_TARGETS:-laser_scan mapper_load scene bag_scans}"
corpus_root="$rfm_source_dir/test/fuzz/corpus"

if [ ! -d "$rfm_ws/devel/include/reflectance_field_map" ]; then
  echo "run_fuzzers.sh: build the workspace $rfm_ws first (scripts/build.sh)" >&2
  exit 2
fi
CC=clang CXX=clang++ cmake -S "$rfm_source_dir/test/fuzz/libfuzzer" -B "$build_dir" \
  -DRFM_DEVEL_INCLUDE="$rfm_ws/devel/include" -DCMAKE_PREFIX_PATH=/usr >/dev/null
cmake --build "$build_dir" -j"$(nproc)" -- --no-print-directory
[ "${RFM_FUZZ_BUILD_ONLY:-0}" = 1 ] && exit 0

# ROS's own allocations that live as long as the process are not leaks of the package.
export LSAN_OPTIONS="suppressions=$rfm_source_dir/test/sanitizers/lsan.supp:print_suppressions=0"
findings="$build_dir/findings"
mkdir -p "$findings"
failed=()
for target in $targets; do
  work="$build_dir/corpus/$target"  # what this run adds; the committed corpus stays as it is
  mkdir -p "$work"
  echo "== fuzzing $target for ${seconds} s"
  log="$build_dir/$target.log"
  if "$build_dir/${target}_fuzzer" "$work" "$corpus_root/$target" \
      -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="$findings/$target-" >"$log" 2>&1; then
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$log" | sed "s/^/  $target /"
  else
    echo "  $target FAILED: $(grep -m1 -E "ERROR: |runtime error|Test unit written" "$log" || true)"
    tail -n 40 "$log"
    failed+=("$target")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzzing found a crash in: ${failed[*]} (inputs in $findings)" >&2
  exit 1
fi
echo "fuzzing: no crash in ${seconds} s each of: $targets"
