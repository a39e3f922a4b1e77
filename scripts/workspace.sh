# Sourced by the other scripts: where the checkout and its catkin workspace are, in one place.
#   rfm_source_dir  the checkout
#   rfm_ws          the workspace: $RFM_WS, by default rfm_ws beside the checkout
#   rfm_shared_data the recordings beside the checkout (../shared/data)
#   rfm_setup       installs the dependencies and any packages named as its arguments (unless
#                   RFM_SKIP_INSTALL=1) and builds
#   rfm_activate    sources the workspace (rosrun, roslaunch, rostest)
#   rfm_wrap        prints its argument as report text, wrapped within 100 columns
export PATH=/usr/bin:$PATH  # Debian's python3: a pyenv python3 breaks catkin
rfm_source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
rfm_ws="${RFM_WS:-$(dirname "$rfm_source_dir")/rfm_ws}"
rfm_shared_data="$(dirname "$rfm_source_dir")/shared/data"

rfm_setup() {
  if [ "${RFM_SKIP_INSTALL:-0}" != 1 ]; then bash "$rfm_source_dir/scripts/install_deps.sh" "$@"; fi
  bash "$rfm_source_dir/scripts/build.sh"
}

rfm_wrap() {
  printf '%s\n' "$1" | fold -s -w 100 | sed 's/ *$//'
}

rfm_activate() {
  set +u  # setup.bash reads unset variables
  # shellcheck disable=SC1091
  source "$rfm_ws/devel/setup.bash"
  set -u
}
