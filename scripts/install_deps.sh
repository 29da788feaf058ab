#!/usr/bin/env bash
# Installs the Debian 12 packages occlusion_env needs, skipping those already installed.
# Usage: scripts/install_deps.sh [--with-viz]   (--with-viz adds rviz, Xvfb and the screenshot
# tools: xwd from x11-apps, ImageMagick's convert)
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake pkg-config git
  # ROS 1 from Debian (no separate prefix) and the Python modules the shell tools need
  ros-base-dev catkin python3-catkin-pkg libroscpp-dev libtf2-ros-dev libtf2-eigen-dev
  libimage-transport-dev libcv-bridge-dev libvisualization-msgs-dev libsensor-msgs-dev
  libmessage-filters-dev
  libgeometry-msgs-dev libstd-srvs-dev python3-rostest rosbash python3-roslaunch
  python3-rosservice python3-rostopic python3-rosnode python3-sensor-msgs python3-geometry-msgs
  python3-tf2-msgs python3-visualization-msgs python3-std-srvs python3-tf2-ros tf-tools
  # message and service generation for the ROS interface (msg/, srv/)
  ros-message-generation ros-message-runtime python3-genmsg python3-gencpp python3-genpy
  libstd-msgs-dev python3-std-msgs librostest-dev
  # the tf package's manifest, so that `rosrun tf tf_echo` finds tf-tools' executables
  libtf-dev
  # core libraries
  libeigen3-dev libopencv-dev libassimp-dev libosmesa6-dev libmeshoptimizer-dev libzip-dev
  libyaml-cpp-dev nlohmann-json3-dev libcli11-dev
  # the learning library: libtorch, and OpenBLAS so that its convolutions do not run on the
  # reference BLAS (5-8x slower; doc/BENCHMARKS.md)
  libtorch-dev libopenblas0-openmp
  # point clouds from the simulator's depth (sim.launch points:=true)
  libdepth-image-proc-dev libnodeletlib-tools
  # tests and benchmarks
  libgtest-dev libbenchmark-dev
  # libFuzzer on the parsers (test/fuzz)
  clang libclang-rt-14-dev
  # objects: Sweet Home 3D furniture (our ShapeNet substitute), statistics engine
  sweethome3d-furniture jags
  # evaluation plots (scripts/plot_evaluation.py)
  python3-matplotlib
)
if [[ "${1:-}" == "--with-viz" ]]; then
  packages+=(rviz xvfb x11-apps imagemagick)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
echo "install_deps: installing ${#missing[@]} missing packages: ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
