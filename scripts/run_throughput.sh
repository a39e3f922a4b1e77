#!/usr/bin/env bash
# Measures rfm_offline's throughput (the full RFM, whole runs: bag reading and label writing
# included) on every shipped scene. Runs the scenes round-robin ROUNDS times, so that a slow
# minute of a shared machine spreads over all of them, and prints each scene's median, fastest
# and slowest real-time factor (timing.real_time_factor of summary.json) as a markdown table.
#
#   scripts/run_throughput.sh
#
# Environment:
#   RFM_WS   catkin workspace with the built package (default: rfm_ws beside the checkout)
#   OUT      scratch directory; a scene's bag is OUT/<scene>/sim.bag, simulated when missing, so
#            run_evaluation.sh's bags are reused (default: /tmp/rfm_eval)
#   SCENES   space-separated scene names (default: every config/scenes/*.yaml)
#   ROUNDS   runs per scene (default: 5)
#   PARAMS   optional rfm_offline --params file
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/workspace.sh"
REPO="$rfm_source_dir"
OUT="${OUT:-/tmp/rfm_eval}"
ROUNDS="${ROUNDS:-5}"

if [[ ! -f "$rfm_ws/devel/setup.bash" ]]; then
  echo "run_throughput.sh: $rfm_ws/devel/setup.bash not found; build the workspace or set RFM_WS" >&2
  exit 1
fi
rfm_activate

if [[ -z "${SCENES:-}" ]]; then
  SCENES="$(cd "$REPO/config/scenes" && ls -1 ./*.yaml | sed 's|^\./||; s|\.yaml$||' | tr '\n' ' ')"
fi
flags=()
[[ -n "${PARAMS:-}" ]] && flags=(--params "$PARAMS")

for scene in $SCENES; do
  if [[ ! -f "$OUT/$scene/sim.bag" ]]; then
    echo "== $scene: simulating" >&2
    mkdir -p "$OUT/$scene"
    rosrun reflectance_field_map rfm_sim --scene "$REPO/config/scenes/$scene.yaml" \
      --out "$OUT/$scene/sim.bag" > /dev/null
  fi
done

TIMES="$OUT/throughput.txt"  # one line per run: scene, real-time factor, wall s
: > "$TIMES"
for round in $(seq "$ROUNDS"); do
  for scene in $SCENES; do
    dir="$OUT/$scene/throughput"
    rm -rf "$dir"
    rosrun reflectance_field_map rfm_offline --bag "$OUT/$scene/sim.bag" --out "$dir" \
      ${flags[@]+"${flags[@]}"} > /dev/null 2>&1 ||
      { echo "run_throughput.sh: rfm_offline failed on $scene" >&2; exit 1; }
    python3 -c '
import json, sys
timing = json.load(open(sys.argv[2]))["timing"]
print(sys.argv[1], timing["real_time_factor"], timing["wall_s"])' \
      "$scene" "$dir/summary.json" >> "$TIMES"
    echo "== round $round/$ROUNDS: $(tail -n 1 "$TIMES")" >&2
  done
done

python3 - "$TIMES" "$ROUNDS" "$(git -C "$REPO" rev-parse --short HEAD 2>/dev/null || echo unknown)" <<'PY'
import collections, statistics, sys
runs = collections.OrderedDict()
for line in open(sys.argv[1]):
    scene, factor, _ = line.split()
    runs.setdefault(scene, []).append(float(factor))
print(f"rfm_offline, full RFM, commit {sys.argv[3]}, {sys.argv[2]} rounds, times real time:")
print()
print("| scene | median | fastest | slowest | >= 25x (median) |")
print("|---|---:|---:|---:|:---:|")
for scene, factors in runs.items():
    median = statistics.median(factors)
    print(f"| {scene} | {median:.1f} | {max(factors):.1f} | {min(factors):.1f} | "
          f"{'yes' if median >= 25.0 else 'no'} |")
PY
