#!/usr/bin/env bash
# Installs the dependencies (unless RFM_SKIP_INSTALL=1), builds, and runs every test (gtest
# units, rostests, the rviz screenshot check) through ctest. Exits non-zero if any test fails.
set -euo pipefail
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ "${RFM_SKIP_INSTALL:-0}" != 1 ]; then bash "$source_dir/scripts/install_deps.sh"; fi
bash "$source_dir/scripts/build.sh"
export PATH=/usr/bin:$PATH
ws="${RFM_WS:-$(dirname "$source_dir")/rfm_ws}"
set +u
source "$ws/devel/setup.bash"
set -u
cd "$ws/build"
ctest --output-on-failure -j1
