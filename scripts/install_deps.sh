#!/usr/bin/env bash
# Installs everything the package needs to build, test and run, from Debian 12's archive
# (ROS 1 ships as Debian packages under /usr: nothing to source); clang and its runtimes build
# the fuzz targets (scripts/run_fuzzers.sh); packages named as arguments go in too. Run as root.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends \
  build-essential cmake catkin ros-message-generation ros-std-msgs ros-std-srvs \
  ros-geometry-msgs ros-sensor-msgs ros-nav-msgs ros-map-msgs ros-visualization-msgs \
  libroscpp-dev librosbag-dev libtf2-ros-dev libtf2-eigen-dev libtf2-geometry-msgs-dev \
  libsensor-msgs-dev libnav-msgs-dev libmap-msgs-dev libvisualization-msgs-dev libstd-srvs-dev \
  libnodeletlib-dev libnodelet-dev pluginlib-dev libdiagnostic-updater-dev \
  librostest-dev python3-rostest libgtest-dev libeigen3-dev libyaml-cpp-dev libpng-dev zlib1g-dev \
  libbenchmark-dev liboctomap-dev \
  python3-rostopic python3-rosnode python3-roslaunch python3-rosservice rosbash tf2-tools \
  libnodeletlib-tools \
  python3-sensor-msgs python3-nav-msgs python3-tf2-msgs python3-visualization-msgs python3-std-srvs \
  python3-diagnostic-msgs python3-rosbag python3-numpy python3-yaml \
  rviz xvfb xauth imagemagick \
  clang libclang-rt-dev \
  "$@"  # packages a caller adds (run_peers.sh: MRPT)
