#!/usr/bin/env bash
# Regenerates doc/evaluation.md: simulates every shipped scene (config/scenes/*.yaml), maps each
# bag with rfm_offline in the four configurations of the paper's Tables II and III, scores the
# per-beam labels against the simulator's ground truth and each classes.pgm against the scene's
# materials with rfm_eval, and aggregates the results (ray- and cell-weighted over all scenes) into
# one markdown file.
#
#   scripts/run_evaluation.sh
#
# Environment:
#   RFM_WS       catkin workspace with the built package (default: rfm_ws beside the checkout)
#   OUT          scratch directory for bags and per-run results (default: /tmp/rfm_eval)
#   SCENES       space-separated scene names to run (default: every config/scenes/*.yaml)
#   REPORT       output file (default: doc/evaluation.md in the checkout)
#   RFM_OFFLINE  mapper command (default: "rosrun reflectance_field_map rfm_offline"); it is called
#                as: $RFM_OFFLINE --bag SIM.bag --out DIR [config flags] and must write
#                DIR/labels.bag (/rfm/ray_labels) and DIR/classes.pgm
set -euo pipefail
export PATH=/usr/bin:$PATH

cd "$(dirname "${BASH_SOURCE[0]}")"
REPO="$(git rev-parse --show-toplevel)"
source "$REPO/scripts/workspace.sh"
RFM_WS="$rfm_ws"
OUT="${OUT:-/tmp/rfm_eval}"
REPORT="${REPORT:-$REPO/doc/evaluation.md}"
read -r -a OFFLINE <<< "${RFM_OFFLINE:-rosrun reflectance_field_map rfm_offline}"

if [[ ! -f "$RFM_WS/devel/setup.bash" ]]; then
  echo "run_evaluation.sh: $RFM_WS/devel/setup.bash not found; build the workspace or set RFM_WS" >&2
  exit 1
fi
set +u  # setup.bash reads unset variables
# shellcheck disable=SC1091
source "$RFM_WS/devel/setup.bash"
set -u

if [[ -z "${SCENES:-}" ]]; then
  SCENES="$(cd "$REPO/config/scenes" && ls -1 ./*.yaml | sed 's|^\./||; s|\.yaml$||' | tr '\n' ' ')"
fi

# Configuration name (Table III row) -> rfm_offline flags.
CONFIG_NAMES=(occupancy_grid basic_rfm +motion_removal +reflection_removal)
CONFIG_FLAGS=("--baseline" "--no-motion-removal --no-reflection-removal" "--no-reflection-removal" "")

mkdir -p "$OUT"
MANIFEST="$OUT/manifest.txt"
: > "$MANIFEST"

for scene in $SCENES; do
  scene_file="$REPO/config/scenes/$scene.yaml"
  [[ -f "$scene_file" ]] || { echo "run_evaluation.sh: no scene $scene_file" >&2; exit 1; }
  mkdir -p "$OUT/$scene"
  echo "== $scene: simulating"
  rosrun reflectance_field_map rfm_sim --scene "$scene_file" --out "$OUT/$scene/sim.bag"
  for i in "${!CONFIG_NAMES[@]}"; do
    config="${CONFIG_NAMES[$i]}"
    dir="$OUT/$scene/${config#+}"
    read -r -a flags <<< "${CONFIG_FLAGS[$i]}"
    echo "== $scene: $config (${CONFIG_FLAGS[$i]:-full})"
    rm -rf "$dir" && mkdir -p "$dir"
    "${OFFLINE[@]}" --bag "$OUT/$scene/sim.bag" --out "$dir" ${flags[@]+"${flags[@]}"} \
      > "$dir/offline.log" 2>&1 || { cat "$dir/offline.log" >&2; exit 1; }
    rosrun reflectance_field_map rfm_eval --truth "$OUT/$scene/sim.bag" \
      --labels "$dir/labels.bag" --scene "$scene_file" --out "$dir/eval" > "$dir/eval.log"
    echo "$config $scene $dir/eval.json" >> "$MANIFEST"
  done
done

PREAMBLE="$OUT/preamble.md"
{
  echo "Reproduce:"
  echo
  echo '    scripts/run_evaluation.sh      # RFM_WS=<catkin ws> OUT=/tmp/rfm_eval'
  echo
  echo "Generated $(date -u +%Y-%m-%d) from commit \`$(git -C "$REPO" rev-parse --short HEAD)\`"
  echo "with scenes: $SCENES."
  echo
  echo "Configurations (rfm_offline flags): occupancy_grid = \`--baseline\` (plain occupancy grid,"
  echo "Table II); basic_rfm = \`--no-motion-removal --no-reflection-removal\`; +motion_removal ="
  echo "\`--no-reflection-removal\`; +reflection_removal = full RFM (Table I)."
} > "$PREAMBLE"

mkdir -p "$(dirname "$REPORT")"
rosrun reflectance_field_map rfm_eval --report "$MANIFEST" --out "$REPORT" --preamble "$PREAMBLE"
echo "== wrote $REPORT"
