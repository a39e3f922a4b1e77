#!/usr/bin/env bash
# Installs the dependencies (unless RFM_SKIP_INSTALL=1), builds, and runs every test (gtest
# units, rostests, the rviz screenshot check) through ctest. Exits non-zero if any test fails.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/workspace.sh"
rfm_setup
rfm_activate
# The rostests start their own masters and nodes on this machine: over localhost they run even
# where the hostname does not resolve.
export ROS_HOSTNAME=localhost
cd "$rfm_ws/build"
ctest --output-on-failure -j1
