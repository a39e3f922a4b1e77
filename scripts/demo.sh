#!/usr/bin/env bash
# The main job on the bundled default scene: installs the dependencies (unless
# RFM_SKIP_INSTALL=1), builds, simulates the atrium (config/scenes/atrium.yaml: glass ring,
# metal doors, people), maps it with rfm_offline and writes the map picture.
#   Output: ${OUT:-/tmp/rfm_demo}/map/{layers.png,map.pgm,map.yaml,labels.bag,summary.json}
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/workspace.sh"
rfm_setup
rfm_activate
out="${OUT:-/tmp/rfm_demo}"
mkdir -p "$out"
rosrun reflectance_field_map rfm_sim --scene "$rfm_source_dir/config/scenes/atrium.yaml" \
  --out "$out/atrium.bag"
rosrun reflectance_field_map rfm_offline --bag "$out/atrium.bag" --out "$out/map" \
  --theta-view 6.01,-3.6,6.01,3.6
rosrun reflectance_field_map rfm_eval --truth "$out/atrium.bag" --labels "$out/map/labels.bag"
echo "map picture: $out/map/layers.png (theta view of the east glass: $out/map/theta_view.png)"
