#!/usr/bin/env bash
# Measures rfm_offline's throughput, whole runs (bag reading and label writing included): the full
# RFM and, right after it on the same bag, the plain grid (--baseline). Bags: every shipped scene
# and the random checking seeds of every sensor setup (rfm_sim --random SEED --setup SETUP). The
# bags run round-robin ROUNDS times, so that a slow minute of a shared machine spreads over all
# of them. Prints per bag, as a markdown table: the full RFM's median real-time factor
# (timing.real_time_factor of summary.json), the plain grid's, and the median of the per-round
# ratios of their wall times (full / plain, measured side by side).
#
#   scripts/run_throughput.sh
#
# Environment:
#   RFM_WS   catkin workspace with the built package (default: rfm_ws beside the checkout)
#   OUT      scratch directory; a scene's bag is OUT/<scene>/sim.bag, a seed's
#            OUT/random/<setup>_<seed>.bag, simulated when missing, so run_evaluation.sh's bags
#            are reused (default: /tmp/rfm_eval)
#   SCENES   space-separated scene names (default: every config/scenes/*.yaml)
#   SEEDS    random checking seeds (default: "1001 1002"; empty: none)
#   SETUPS   sensor setups for the seeds (default: every name rfm_sim --list-setups prints)
#   ROUNDS   runs per bag and mode (default: 5)
#   MODES    the runs on each bag, in order (default: "full plain"); add "no_alg3"
#            (--no-reflection-removal: Alg. 1 and 2 without Alg. 3's passes) to show what the
#            full RFM's passes cost over the plain grid
#   PARAMS   optional rfm_offline --params file
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/workspace.sh"
REPO="$rfm_source_dir"
OUT="${OUT:-/tmp/rfm_eval}"
ROUNDS="${ROUNDS:-5}"
SEEDS="${SEEDS-1001 1002}"
MODES="${MODES:-full plain}"
for mode in $MODES; do
  case "$mode" in
    full | plain | no_alg3) ;;
    *) echo "run_throughput.sh: MODES holds '$mode'; allowed: full, plain, no_alg3" >&2; exit 2 ;;
  esac
done
[[ " $MODES " == *" full "* && " $MODES " == *" plain "* ]] ||
  { echo "run_throughput.sh: MODES must hold full and plain" >&2; exit 2; }

if [[ ! -f "$rfm_ws/devel/setup.bash" ]]; then
  echo "run_throughput.sh: $rfm_ws/devel/setup.bash not found; build the workspace or set RFM_WS" >&2
  exit 1
fi
rfm_activate

if [[ -z "${SCENES:-}" ]]; then
  SCENES="$(cd "$REPO/config/scenes" && ls -1 ./*.yaml | sed 's|^\./||; s|\.yaml$||' | tr '\n' ' ')"
fi
if [[ -z "${SETUPS:-}" ]]; then
  SETUPS="$(rosrun reflectance_field_map rfm_sim --list-setups |
    sed -n 's/^\([a-z0-9_]*\): .*/\1/p' | tr '\n' ' ')"
fi
flags=()
[[ -n "${PARAMS:-}" ]] && flags=(--params "$PARAMS")

scan_topics_of() {  # the bag's sensor_msgs/LaserScan topics, comma-separated
  python3 - "$1" <<'PY'
import sys
import rosbag
with rosbag.Bag(sys.argv[1]) as bag:
    info = bag.get_type_and_topic_info().topics
print(",".join(sorted(t for t, i in info.items() if i.msg_type == "sensor_msgs/LaserScan")))
PY
}

names=()
bags=()
for scene in $SCENES; do
  bag="$OUT/$scene/sim.bag"
  if [[ ! -f "$bag" ]]; then
    echo "== $scene: simulating" >&2
    mkdir -p "$OUT/$scene"
    rosrun reflectance_field_map rfm_sim --scene "$REPO/config/scenes/$scene.yaml" --out "$bag" \
      > /dev/null
  fi
  names+=("$scene")
  bags+=("$bag")
done
for setup in $SETUPS; do
  for seed in $SEEDS; do
    bag="$OUT/random/${setup}_$seed.bag"
    if [[ ! -f "$bag" ]]; then
      echo "== $setup seed $seed: simulating" >&2
      mkdir -p "$OUT/random"
      rosrun reflectance_field_map rfm_sim --random "$seed" --setup "$setup" --out "$bag" \
        > /dev/null
    fi
    names+=("${setup}_$seed")
    bags+=("$bag")
  done
done
topics=()
for bag in "${bags[@]}"; do topics+=("$(scan_topics_of "$bag")"); done

TIMES="$OUT/throughput.txt"  # one line per run: bag name, mode, real-time factor, wall s
: > "$TIMES"
for round in $(seq "$ROUNDS"); do
  for i in "${!bags[@]}"; do
    for mode in $MODES; do
      dir="$OUT/throughput/${names[$i]}_$mode"
      rm -rf "$dir"
      mode_flags=()
      [[ "$mode" == plain ]] && mode_flags=(--baseline)
      [[ "$mode" == no_alg3 ]] && mode_flags=(--no-reflection-removal)
      rosrun reflectance_field_map rfm_offline --bag "${bags[$i]}" --out "$dir" \
        --scan-topics "${topics[$i]}" ${flags[@]+"${flags[@]}"} ${mode_flags[@]+"${mode_flags[@]}"} > /dev/null 2>&1 ||
        { echo "run_throughput.sh: rfm_offline failed on ${bags[$i]} ($mode)" >&2; exit 1; }
      python3 -c '
import json, sys
timing = json.load(open(sys.argv[3]))["timing"]
print(sys.argv[1], sys.argv[2], timing["real_time_factor"], timing["wall_s"])' \
        "${names[$i]}" "$mode" "$dir/summary.json" >> "$TIMES"
    done
    echo "== round $round/$ROUNDS: $(tail -n "$(wc -w <<< "$MODES")" "$TIMES" | tr '\n' ' ')" >&2
  done
done

python3 - "$TIMES" "$ROUNDS" "$(git -C "$REPO" rev-parse --short HEAD 2>/dev/null || echo unknown)" <<'PY'
import collections, statistics, sys
factors = collections.OrderedDict()  # name -> mode -> [real-time factor]
walls = collections.defaultdict(list)
for line in open(sys.argv[1]):
    name, mode, factor, wall = line.split()
    factors.setdefault(name, collections.OrderedDict()).setdefault(mode, []).append(float(factor))
    walls[name, mode].append(float(wall))
extra = "no_alg3" in next(iter(factors.values()))
print(f"rfm_offline, commit {sys.argv[3]}, {sys.argv[2]} rounds, times real time "
      "(median of the rounds) and the full RFM's wall time over the plain grid's (median of "
      "the per-round ratios):")
print()
header, rule = "| bag | full RFM | plain grid | full / plain |", "|---|---:|---:|---:|"
if extra:
    header += " without Alg. 3 | without Alg. 3 / plain |"
    rule += "---:|---:|"
print(header + " >= 50x | <= 1.5x |")
print(rule + ":---:|:---:|")
def ratio(name, mode):  # median of the per-round ratios of the wall times, mode over plain
    return statistics.median(a / b for a, b in zip(walls[name, mode], walls[name, "plain"]))
for name, modes in factors.items():
    full = statistics.median(modes["full"])
    plain = statistics.median(modes["plain"])
    row = f"| {name} | {full:.1f}x | {plain:.1f}x | {ratio(name, 'full'):.2f} |"
    if extra:
        row += f" {statistics.median(modes['no_alg3']):.1f}x | {ratio(name, 'no_alg3'):.2f} |"
    print(row + f" {'yes' if full >= 50.0 else 'no'} | "
          f"{'yes' if ratio(name, 'full') <= 1.5 else 'no'} |")
PY
