#!/usr/bin/env bash
# Builds the package with AddressSanitizer and UndefinedBehaviorSanitizer (clang,
# -DRFM_SANITIZE=ON) in a second catkin workspace, $RFM_SANITIZE_WS (by default rfm_ws_asan
# beside the checkout), and runs every test there. The nodelet test's stock manager gets the
# sanitizer runtime preloaded (RFM_NODELET_LAUNCH_PREFIX, read by
# test/ros/synthetic_scene_nodelet.test). Every
# process writes its sanitizer reports under the workspace's sanitizer_reports/: any report
# (memory error, undefined behaviour, leak), even from a node that exits after its test has
# passed, fails the run. Extra arguments go to ctest instead (e.g. -R sim_test).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/sanitize_workspace.sh"
if [ "${RFM_SKIP_INSTALL:-0}" != 1 ]; then bash "$rfm_source_dir/scripts/install_deps.sh"; fi
rfm_sanitize_build
ws="$rfm_sanitize_ws"

reports="$ws/sanitizer_reports"
rm -rf "$reports"
mkdir -p "$reports"
supp="$rfm_source_dir/test/sanitizers"
export ASAN_OPTIONS="log_path=$reports/asan:detect_leaks=1"
export UBSAN_OPTIONS="log_path=$reports/ubsan:print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
# The stock nodelet manager is not built with the sanitizers: it needs their runtime (ASan's,
# which holds UBSan's) loaded first.
export RFM_NODELET_LAUNCH_PREFIX="env LD_PRELOAD=$(clang -print-file-name=libclang_rt.asan-x86_64.so)"

set +u  # setup.bash reads unset variables
# shellcheck disable=SC1091
source "$ws/devel/setup.bash"
set -u
cd "$ws/build"
status=0
if [ $# -gt 0 ]; then
  ctest --output-on-failure "$@" || status=$?
else
  # The units two at a time (each is one process, its CPU its own); the node tests, which wait
  # on their nodes' timing, one at a time. The real recordings' evaluation (test/real: minutes
  # in the ordinary build, far longer here) runs only with RFM_SANITIZE_REAL_DATA=1: the tools
  # it drives are run by the end-to-end tests here.
  slow='rostest|rviz'
  real='^real_'
  [ "${RFM_SANITIZE_REAL_DATA:-0}" = 1 ] && real='^$'
  ctest --output-on-failure -j2 -E "$slow|$real" || status=$?
  ctest --output-on-failure -j1 -R "$slow" || status=$?
fi
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
