#!/usr/bin/env bash
# Runs the benchmarks as recorded in doc/benchmarks.md: every benchmark repeated 7 times,
# repetitions randomly interleaved so that ratios are measured side by side, medians reported.
# Run on a quiet machine, after scripts/build.sh.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../../scripts/workspace.sh"
"$rfm_ws/devel/lib/reflectance_field_map/rfm_benchmark" --benchmark_repetitions=7 \
  --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true "$@"
