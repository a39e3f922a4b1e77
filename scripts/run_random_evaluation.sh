#!/usr/bin/env bash
# Regenerates doc/random_evaluation.md: for each sensor setup, simulates procedural scenes
# (rfm_sim --random SEED --setup SETUP), maps every bag with rfm_offline (the full RFM and the
# plain occupancy grid, --baseline) and labels it as the live node does (rfm_live_labels), scores
# the labels and the class map against the simulator's truth and world with rfm_eval, and writes
# one report grouped by setup and seed split.
#
#   scripts/run_random_evaluation.sh                  # 5-20 minutes: 10 checking seeds, 40 s each
#   SEEDS="$(seq 1001 1030)" DURATION= scripts/run_random_evaluation.sh   # bigger
#
# Seeds are split in two, once and for all:
#   tuning seeds   1-100      may be used to choose a rule or a number;
#   checking seeds 1001-1100  are only ever reported, never used to choose anything.
# Any other seed is reported as "other".
#
# Environment:
#   SEEDS        seeds to simulate (default: 1001 to 1010)
#   SETUPS       sensor setups (default: every name rfm_sim --list-setups prints)
#   DURATION     seconds of each scene (default 40; empty: each seed draws 40-80 s)
#   OUT          scratch directory for bags, maps and scores (default: /tmp/rfm_random_eval)
#   REPORT       output file (default: doc/random_evaluation.md in the checkout)
#   FIXED_FRAME  frame the maps are made in (default odom, as the node: with the odometry's
#                drift; map: the true localisation every random scene's bag also holds)
#   RFM_WS       catkin workspace with the built package (default: rfm_ws beside the checkout)
#   RFM_OFFLINE  mapper command (default: "rosrun reflectance_field_map rfm_offline"), called as
#                $RFM_OFFLINE --bag SIM.bag --out DIR --scan-topics /a[,/b] --fixed-frame F
#                [--baseline]; it must
#                write DIR/labels.bag, DIR/map.yaml and DIR/classes.pgm
set -euo pipefail
export PATH=/usr/bin:$PATH

cd "$(dirname "${BASH_SOURCE[0]}")"
REPO="$(git rev-parse --show-toplevel)"
source "$REPO/scripts/workspace.sh"
OUT="${OUT:-/tmp/rfm_random_eval}"
REPORT="${REPORT:-$REPO/doc/random_evaluation.md}"
SEEDS="${SEEDS:-$(seq 1001 1010)}"
DURATION="${DURATION-40}"
FIXED_FRAME="${FIXED_FRAME:-odom}"
read -r -a OFFLINE <<< "${RFM_OFFLINE:-rosrun reflectance_field_map rfm_offline}"

if [[ ! -f "$rfm_ws/devel/setup.bash" ]]; then
  echo "run_random_evaluation.sh: $rfm_ws/devel/setup.bash not found; build the workspace or set" \
    "RFM_WS" >&2
  exit 1
fi
rfm_activate

if [[ -z "${SETUPS:-}" ]]; then
  SETUPS="$(rosrun reflectance_field_map rfm_sim --list-setups | sed -n 's/^\([a-z0-9_]*\): .*/\1/p' |
    tr '\n' ' ')"
fi

split_of() {
  if (($1 >= 1 && $1 <= 100)); then
    echo tuning
  elif (($1 >= 1001 && $1 <= 1100)); then
    echo checking
  else
    echo other
  fi
}

# Mapper configurations: name in the report -> rfm_offline flags.
CONFIG_NAMES=(RFM plain_grid)
CONFIG_FLAGS=("" "--baseline")

duration_flag=()
[[ -n "$DURATION" ]] && duration_flag=(--duration "$DURATION")
mkdir -p "$OUT"
MANIFEST="$OUT/manifest.txt"
SCENES="$OUT/scenes.md"
: > "$MANIFEST"
{
  echo
  echo "## Scenes"
  echo
  echo "| setup | seed | split | what rfm_sim drew | odometry drift at the end |"
  echo "|---|---:|---|---|---|"
} > "$SCENES"
start=$(date +%s)

for setup in $SETUPS; do
  for seed in $SEEDS; do
    split="$(split_of "$seed")"
    dir="$OUT/$setup/$seed"
    rm -rf "$dir" && mkdir -p "$dir"
    echo "== $setup, seed $seed ($split): simulating"
    rosrun reflectance_field_map rfm_sim --random "$seed" --setup "$setup" ${duration_flag[@]+"${duration_flag[@]}"} \
      --out "$dir/sim.bag" --write-scene "$dir/scene.yaml" > "$dir/sim.log"
    topics="$(sed -n 's/^  - {topic: \([^,]*\),.*/\1/p' "$dir/scene.yaml" | paste -sd, -)"
    for i in "${!CONFIG_NAMES[@]}"; do
      config="${CONFIG_NAMES[$i]}"
      read -r -a flags <<< "${CONFIG_FLAGS[$i]}"
      echo "== $setup, seed $seed: $config"
      "${OFFLINE[@]}" --bag "$dir/sim.bag" --out "$dir/$config" --scan-topics "$topics" \
        --fixed-frame "$FIXED_FRAME" \
        ${flags[@]+"${flags[@]}"} \
        > "$dir/$config.log" 2>&1 || { cat "$dir/$config.log" >&2; exit 1; }
      rosrun reflectance_field_map rfm_eval --truth "$dir/sim.bag" --labels "$dir/$config/labels.bag" \
        --scene "$dir/scene.yaml" --truth-cells "$dir/$config/truth_cells.pgm" \
        --out "$dir/$config/eval" > "$dir/$config/eval.log"
      echo "$config $seed $dir/$config/eval.json $setup $split" >> "$MANIFEST"
    done
    # The node's labels: each scan judged when it arrives, against the map so far.
    echo "== $setup, seed $seed: RFM_live"
    mkdir -p "$dir/RFM_live"
    rosrun reflectance_field_map rfm_live_labels "$dir/sim.bag" "$dir/RFM_live/labels.bag" \
      --scan-topics "$topics" --fixed-frame "$FIXED_FRAME" \
      --classes-log "$dir/RFM_live/classes.bin" \
      > "$dir/RFM_live.log" 2>&1 || { cat "$dir/RFM_live.log" >&2; exit 1; }
    gzip -f "$dir/RFM_live/classes.bin"  # a fiftieth: the classes are runs of a few values
    rosrun reflectance_field_map rfm_eval --truth "$dir/sim.bag" --labels "$dir/RFM_live/labels.bag" \
      --out "$dir/RFM_live/eval" > "$dir/RFM_live/eval.log"
    echo "RFM_live $seed $dir/RFM_live/eval.json $setup $split" >> "$MANIFEST"
    description="$(sed -n 's/^description: "\(.*\)"$/\1/p' "$dir/scene.yaml")"
    drift="$(sed -n 's/^  odometry drifted \([0-9.e-]*\) m and \([0-9.e-]*\) deg.*/\1 m, \2 deg/p' "$dir/sim.log")"
    [[ "$drift" == "0 m, 0 deg" ]] && drift="none (true poses)"
    echo "| $setup | $seed | $split | ${description//|/\/} | $drift |" >> "$SCENES"
  done
done
minutes=$(( ($(date +%s) - start + 59) / 60 ))

PREAMBLE="$OUT/preamble.md"
{
  echo "Procedural scenes (\`rfm_sim --random SEED --setup SETUP\`, doc/simulator.md) mapped by"
  echo "\`rfm_offline\` with its default parameters (RFM) and as a plain occupancy grid"
  echo "(\`--baseline\`), and labelled as the live node labels them (RFM_live: \`rfm_live_labels\`,"
  echo "each scan judged when it arrives, against the map so far; rays only),"
  echo "in the \`$FIXED_FRAME\` frame, scored by \`rfm_eval\` (rays against"
  echo "\`/sim/ray_truth\`; classes.pgm against the world of the scene file \`rfm_sim --write-scene\`"
  echo "wrote, tolerance 1 cell). In \`odom\` the maps carry the odometry's drift (Scenes, below),"
  echo "which the class metrics count as misplaced cells; \`FIXED_FRAME=map\` maps with true poses."
  echo
  echo "**Seed split.** Tuning seeds are 1-100: rules and numbers may be chosen on them. Checking"
  echo "seeds are 1001-1100: they are only ever reported, never used to choose a rule or a number."
  echo "Rows say which split their seeds belong to."
  echo
  # shellcheck disable=SC2086  # word splitting trims the lists
  echo "This run: setups $(echo $SETUPS); seeds $(echo $SEEDS); ${DURATION:-40-80} s a scene."
  echo "Generated $(date -u +%Y-%m-%d) from commit \`$(git -C "$REPO" rev-parse --short HEAD)\`"
  echo "in about $minutes minute(s) on $(nproc) cores. Reproduce or enlarge it:"
  echo
  echo '    scripts/run_random_evaluation.sh   # SEEDS="$(seq 1001 1010)" SETUPS="..." DURATION=40 FIXED_FRAME=odom OUT=...'
} > "$PREAMBLE"

mkdir -p "$(dirname "$REPORT")"
rosrun reflectance_field_map rfm_eval --report "$MANIFEST" --out "$REPORT" --preamble "$PREAMBLE" \
  --title "Random scenes: evaluation per sensor setup"
{
  echo
  echo "## Kept motion: whose, and were they seen gone"
  echo
  echo "\`scripts/kept_motion.py\` sorts the true motion beams each map kept by the person they hit"
  echo "(the scene file's people, moved as rfm_sim moves them): walking; standing, and still there"
  echo "when the recording ends (stays); standing, left later, and no later beam crossed their"
  echo "footprint with the person a metre or more away (left unseen); or some beam did (left, seen:"
  echo "an upper bound on what a map could have removed), only beams without a return (which the"
  echo "RFM takes for dropouts where they cross structure) or at least one that returned from beyond"
  echo "the spot. The recording never shows the first two kinds of standing gone. Shares of all true"
  echo "motion beams."
  echo
  python3 "$REPO/scripts/kept_motion.py" "$OUT" RFM plain_grid RFM_live
  echo
  echo "## Glass missed: was it ever faced"
  echo
  echo "\`scripts/unseen_glass.py\` sorts the true glass cells that the class metrics count (glass"
  echo "alone in the cell, something other than unknown drawn within a cell) by the face-on echoes"
  echo "that ended within a cell of them: the truth's GLASS beams, placed with the true poses, whose"
  echo "incidence on the pane is within the scene's return cone and whose range is within the RFM's"
  echo "evidence range (the active region's radius, 10 m as in the paper). It gives the RFM's glass"
  echo "recall for each kind. A pane returns near its normal; dirty, a faint scatter from anywhere,"
  echo "and with nothing behind it a weak echo of its own. Those faint echoes fall in direction bins"
  echo "that the rays cross far more often without one, and echoes from beyond 10 m add no evidence:"
  echo "glass the robot never faced within range reads as free space to a map of ray directions."
  echo
  python3 "$REPO/scripts/unseen_glass.py" "$OUT" RFM
  echo
  echo "## Reflections kept live: panes not yet faced"
  echo
  echo "\`scripts/live_reflection_gap.py\` takes the reflection beams that the offline map removes as"
  echo "reflections and the live labels keep, finds the first cell on each that the offline map draws"
  echo "glass or metal, and looks up what the live map held there at the last motion-removal pass"
  echo "before the beam's scan (\`rfm_live_labels --classes-log\`). A pane returns only near its normal:"
  echo "until the robot faces it, the live map holds free space there, and no labeller that judges a"
  echo "scan when it arrives can cut the beams through it. Every 5th such beam scored; shares of those."
  echo
  python3 "$REPO/scripts/live_reflection_gap.py" "$OUT"
} >> "$REPORT"
cat "$SCENES" >> "$REPORT"
echo "== wrote $REPORT"
