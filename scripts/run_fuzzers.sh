#!/usr/bin/env bash
# Runs each libFuzzer target of test/fuzz for RFM_FUZZ_SECONDS (default 30) from its committed
# corpus, two at a time. The sanitizer build (scripts/sanitize_workspace.sh) builds the targets;
# this script builds it when they are missing. Exits non-zero when a target crashes, leaks, hangs (20 s an input) or
# runs out of memory (2 GB); the input that did it is kept in
# $RFM_SANITIZE_WS/fuzz_findings, to add to test/fuzz/corpus/<target> once fixed.
#   RFM_FUZZ_TARGETS="scene laser_scan"  runs only those targets
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/sanitize_workspace.sh"
seconds="${RFM_FUZZ_SECONDS:-30}"
targets="${RFM_FUZZ_TARGETS:-laser_scan mapper_load scene bag_scans carmen_log}"
corpus_root="$rfm_source_dir/test/fuzz/corpus"
bin="$rfm_sanitize_ws/devel/lib/reflectance_field_map"
for target in $targets; do
  if [ ! -x "$bin/rfm_fuzz_$target" ]; then
    if [ "${RFM_SKIP_INSTALL:-0}" != 1 ]; then bash "$rfm_source_dir/scripts/install_deps.sh"; fi
    rfm_sanitize_build
    break
  fi
done

# ROS's own allocations that live as long as the process are not leaks of the package.
export LSAN_OPTIONS="suppressions=$rfm_source_dir/test/sanitizers/lsan.supp:print_suppressions=0"
findings="$rfm_sanitize_ws/fuzz_findings"
runs="$rfm_sanitize_ws/fuzz_runs"
mkdir -p "$findings" "$runs"

fuzz() {  # fuzz TARGET: one bounded run; its log in $runs/TARGET.log
  local target="$1" work="$runs/$1.corpus"  # what this run adds; the committed corpus stays
  mkdir -p "$work"
  "$bin/rfm_fuzz_$target" "$work" "$corpus_root/$target" -max_total_time="$seconds" \
    -timeout=20 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$findings/$target-" >"$runs/$target.log" 2>&1
}

report() {  # report TARGET STATUS
  local target="$1" log="$runs/$1.log"
  if [ "$2" = 0 ]; then
    echo "  $target: $(grep -oE "number_of_executed_units: *[0-9]+" "$log" | grep -oE "[0-9]+") inputs," \
      "$(grep -oE "new_units_added: *[0-9]+" "$log" | grep -oE "[0-9]+") new, peak" \
      "$(grep -oE "peak_rss_mb: *[0-9]+" "$log" | grep -oE "[0-9]+") MB, no crash"
  else
    echo "  $target FAILED: $(grep -m1 -E "ERROR: |runtime error" "$log" || true)"
    tail -n 40 "$log"
    failed+=("$target")
  fi
}

echo "fuzzing for ${seconds} s each, two at a time: $targets"
failed=()
set -- $targets
while [ $# -gt 0 ]; do
  batch=("$1")
  shift
  if [ $# -gt 0 ]; then
    batch+=("$1")
    shift
  fi
  pids=()
  for target in "${batch[@]}"; do
    fuzz "$target" &
    pids+=($!)
  done
  for i in "${!batch[@]}"; do
    status=0
    wait "${pids[$i]}" || status=$?
    report "${batch[$i]}" "$status"
  done
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzzing found a crash in: ${failed[*]} (inputs in $findings)" >&2
  exit 1
fi
echo "fuzzing: no crash in ${seconds} s of each target"
