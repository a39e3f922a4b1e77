# Sourced by run_sanitized_tests.sh and run_fuzzers.sh: the sanitizer build, in one place.
#   rfm_sanitize_ws     its catkin workspace: $RFM_SANITIZE_WS, by default rfm_ws_asan beside the
#                       checkout
#   rfm_sanitize_build  builds there, with clang and -DRFM_SANITIZE=ON (ASan, UBSan and
#                       libFuzzer's coverage), what the tests run and the fuzz targets (target
#                       `tests`: not the benchmarks)
source "$(dirname "${BASH_SOURCE[0]}")/workspace.sh"
rfm_sanitize_ws="${RFM_SANITIZE_WS:-$(dirname "$rfm_source_dir")/rfm_ws_asan}"

rfm_sanitize_build() {
  mkdir -p "$rfm_sanitize_ws/src"
  local link="$rfm_sanitize_ws/src/reflectance_field_map"
  if [ "$(readlink -f "$link" 2>/dev/null)" != "$rfm_source_dir" ]; then
    rm -rf "$link" "$rfm_sanitize_ws/build" "$rfm_sanitize_ws/devel"
    ln -s "$rfm_source_dir" "$link"
  fi
  # -O2 (the tests run Eigen-heavy code, slow at -O1) and line tables only: the reports still
  # name files and lines.
  (cd "$rfm_sanitize_ws" && CC=clang CXX=clang++ catkin_make -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only" -DCATKIN_ENABLE_TESTING=ON \
    -DRFM_WERROR=ON -DRFM_SANITIZE=ON -DPYTHON_EXECUTABLE=/usr/bin/python3 \
    --make-args tests -j"$(nproc)")
}
