#!/usr/bin/env bash
# Scaling of the online update: time and active-region memory per scan as the active-region
# radius (5, 10, 20 m), the theta bins (90, 180, 720) and the beams per scan (270, 1081, 4320)
# each move away from the defaults. Runs BM_Scaling (rfm_benchmark) 5 times, repetitions
# interleaved, and draws the medians into doc/scaling.png (python3-matplotlib, installed from
# Debian's archive if missing). Run on a quiet machine, after scripts/build.sh.
#
#   test/benchmark/run_scaling.sh            # OUT (default /tmp/rfm_scaling) keeps the JSON
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/../../scripts/workspace.sh"
OUT="${OUT:-/tmp/rfm_scaling}"
mkdir -p "$OUT"
if ! /usr/bin/python3 -c 'import matplotlib' 2>/dev/null; then
  apt-get install -y --no-install-recommends python3-matplotlib > /dev/null
fi
"$rfm_ws/devel/lib/reflectance_field_map/rfm_benchmark" --benchmark_filter='^BM_Scaling' \
  --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true \
  --benchmark_report_aggregates_only=true --benchmark_out="$OUT/scaling.json" \
  --benchmark_out_format=json
/usr/bin/python3 "$here/plot_scaling.py" "$OUT/scaling.json" "$rfm_source_dir/doc/scaling.png"
