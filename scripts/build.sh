#!/usr/bin/env bash
# Builds the package (and its tests) in a catkin workspace outside the source tree:
# $RFM_WS, by default rfm_ws beside the checkout. Warnings are errors (-Wall -Wextra -Werror).
set -euo pipefail
export PATH=/usr/bin:$PATH  # Debian's python3: a pyenv python3 breaks catkin
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ws="${RFM_WS:-$(dirname "$source_dir")/rfm_ws}"
mkdir -p "$ws/src"
link="$ws/src/reflectance_field_map"
if [ "$(readlink -f "$link" 2>/dev/null)" != "$source_dir" ]; then
  # A workspace built from another checkout: start it afresh.
  rm -rf "$link" "$ws/build" "$ws/devel"
  ln -s "$source_dir" "$link"
fi
cd "$ws"
catkin_make -DCMAKE_BUILD_TYPE=Release -DCATKIN_ENABLE_TESTING=ON -DRFM_WERROR=ON \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 --make-args all tests -j"$(nproc)"
echo "built in $ws (source $ws/devel/setup.bash)"
