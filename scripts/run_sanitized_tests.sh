#!/usr/bin/env bash
# Builds the package with AddressSanitizer and UndefinedBehaviorSanitizer (-DRFM_SANITIZE=ON)
# in a second catkin workspace, $RFM_SANITIZE_WS (by default rfm_ws_asan beside the checkout),
# and runs every test there. The nodelet test's stock manager gets the sanitizer runtime
# preloaded (RFM_NODELET_LAUNCH_PREFIX, read by test/ros/synthetic_scene_nodelet.test). Every
# process writes its sanitizer reports under the workspace's sanitizer_reports/: any report
# (memory error, undefined behaviour, leak), even from a node that exits after its test has
# passed, fails the run. Extra arguments go to ctest (e.g. -R sim_test).
set -euo pipefail
export PATH=/usr/bin:$PATH  # Debian's python3: a pyenv python3 breaks catkin
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ws="${RFM_SANITIZE_WS:-$(dirname "$source_dir")/rfm_ws_asan}"
if [ "${RFM_SKIP_INSTALL:-0}" != 1 ]; then bash "$source_dir/scripts/install_deps.sh"; fi

mkdir -p "$ws/src"
link="$ws/src/reflectance_field_map"
if [ "$(readlink -f "$link" 2>/dev/null)" != "$source_dir" ]; then
  rm -rf "$link" "$ws/build" "$ws/devel"
  ln -s "$source_dir" "$link"
fi
# -O1: the sanitizers' usual level (fast enough to run every test, quicker to compile).
(cd "$ws" && catkin_make -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCATKIN_ENABLE_TESTING=ON -DRFM_WERROR=ON \
  -DRFM_SANITIZE=ON -DPYTHON_EXECUTABLE=/usr/bin/python3 --make-args all tests -j"$(nproc)")

reports="$ws/sanitizer_reports"
rm -rf "$reports"
mkdir -p "$reports"
supp="$source_dir/test/sanitizers"
export ASAN_OPTIONS="log_path=$reports/asan:detect_leaks=1"
export UBSAN_OPTIONS="log_path=$reports/ubsan:print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
# The stock nodelet manager is not built with the sanitizers: it needs their runtimes first.
export RFM_NODELET_LAUNCH_PREFIX="env LD_PRELOAD=$(gcc -print-file-name=libasan.so):$(gcc -print-file-name=libubsan.so)"

set +u  # setup.bash reads unset variables
# shellcheck disable=SC1091
source "$ws/devel/setup.bash"
set -u
cd "$ws/build"
status=0
ctest --output-on-failure -j1 "$@" || status=$?
if compgen -G "$reports/*" >/dev/null; then
  echo "sanitizer reports (each fails the run):"
  for report in "$reports"/*; do
    echo "== $report"
    head -n 60 "$report"
  done
  status=1
fi
if [ "$status" = 0 ]; then
  echo "sanitized tests: all passed, no sanitizer report"
fi
exit "$status"
