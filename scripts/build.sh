#!/usr/bin/env bash
# Builds the package (and its tests) in a catkin workspace outside the source tree:
# $RFM_WS, by default rfm_ws beside the checkout. Warnings are errors (-Wall -Wextra -Werror).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/workspace.sh"
mkdir -p "$rfm_ws/src"
link="$rfm_ws/src/reflectance_field_map"
if [ "$(readlink -f "$link" 2>/dev/null)" != "$rfm_source_dir" ]; then
  # A workspace built from another checkout: start it afresh.
  rm -rf "$link" "$rfm_ws/build" "$rfm_ws/devel"
  ln -s "$rfm_source_dir" "$link"
fi
cd "$rfm_ws"
catkin_make -DCMAKE_BUILD_TYPE=Release -DCATKIN_ENABLE_TESTING=ON -DRFM_WERROR=ON \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 --make-args all tests -j"$(nproc)"
echo "built in $rfm_ws (source $rfm_ws/devel/setup.bash)"
