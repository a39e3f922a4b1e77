#!/usr/bin/env bash
# Prints the sha256 of every output that a change meant to keep results identical must keep:
# labels.bag, map.pgm and layers.png of rfm_offline on each shipped scene (full RFM and the
# plain-grid baseline) and on the real stationary recording. Compare two builds with diff.
#
#   scripts/output_hashes.sh > /tmp/before.txt      # RFM_WS=<catkin ws> OUT=/tmp/rfm_hashes
#
# Environment:
#   RFM_WS  catkin workspace with the built package (default: rfm_ws beside the checkout)
#   OUT     scratch directory for bags and maps (default: /tmp/rfm_hashes); simulated bags in
#           it are reused
#   SCENES  space-separated scene names (default: every config/scenes/*.yaml)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/workspace.sh"
rfm_activate
out="${OUT:-/tmp/rfm_hashes}"
scenes="${SCENES:-$(cd "$rfm_source_dir/config/scenes" && ls -1 ./*.yaml | sed 's|^\./||; s|\.yaml$||')}"
real_bag="$rfm_shared_data/real/demo_stationary_simple_environment.bag"
mkdir -p "$out"

hash_outputs() {  # NAME DIR
  for file in labels.bag map.pgm layers.png; do
    printf '%s  %s/%s\n' "$(sha256sum < "$2/$file" | cut -d' ' -f1)" "$1" "$file"
  done
}

map() {  # NAME BAG [rfm_offline flags]
  local name="$1" bag="$2" dir="$out/$1"
  shift 2
  rm -rf "$dir"
  rosrun reflectance_field_map rfm_offline --bag "$bag" --out "$dir" "$@" > "$dir.log" 2>&1 ||
    { cat "$dir.log" >&2; exit 1; }
  hash_outputs "$name" "$dir"
}

for scene in $scenes; do
  bag="$out/$scene.bag"
  if [ ! -f "$bag" ]; then
    rosrun reflectance_field_map rfm_sim --scene "$rfm_source_dir/config/scenes/$scene.yaml" \
      --out "$bag" > /dev/null
  fi
  map "$scene" "$bag"
  map "$scene/baseline" "$bag" --baseline
done
if [ -f "$real_bag" ]; then
  map stationary "$real_bag" --fixed-frame laser --scan-topics /scan
  map stationary/baseline "$real_bag" --fixed-frame laser --scan-topics /scan --baseline
fi
