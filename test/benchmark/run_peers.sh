#!/usr/bin/env bash
# Peers side by side on the same rays: the RFM with every stage (rfm_offline), the plain
# occupancy grid (rfm_offline --baseline), OctoMap inserting the same rays as a planar slice
# at the same resolution (rfm_octomap_peer) and MRPT's 2D occupancy grid inserting the same
# beams (rfm_mrpt_peer), on Freiburg 079 and the Freiburg campus
# (rfm_carmen2bag of ../shared/data/real) and on the shipped atrium scene (rfm_sim). The four
# run one after the other on each recording, ROUNDS rounds; per mapper the medians of: scans
# mapped per second of its mapping (bag reading and output writing left out: the same reader
# serves all four) and its process's peak resident memory (the scans it holds included, for all
# four alike). Prints a markdown table. Run on a quiet machine, as root: it installs MRPT's
# libmrpt-maps-dev (not a dependency of the package; RFM_SKIP_INSTALL=1 skips the installs, and a
# mapper whose program is not built is left out) and builds.
#
#   test/benchmark/run_peers.sh              # OUT (default /tmp/rfm_peers), ROUNDS (default 3)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/../../scripts/workspace.sh"
OUT="${OUT:-/tmp/rfm_peers}"
ROUNDS="${ROUNDS:-3}"
DATA="$rfm_source_dir/../shared/data/real"
rfm_setup libmrpt-maps-dev >&2  # stdout: the table
rfm_activate
mkdir -p "$OUT"
for log in freiburg-079 freiburg-campus; do
  [[ -f "$OUT/$log.bag" ]] || rosrun reflectance_field_map rfm_carmen2bag \
    "$DATA/$log-corrected.log.gz" "$OUT/$log.bag" > /dev/null
done
[[ -f "$OUT/atrium.bag" ]] || rosrun reflectance_field_map rfm_sim \
  --scene "$rfm_source_dir/config/scenes/atrium.yaml" --out "$OUT/atrium.bag" > /dev/null
/usr/bin/python3 "$here/peers.py" "$OUT" "$ROUNDS" "$rfm_ws/devel/lib/reflectance_field_map"
