#!/usr/bin/env bash
# The ROS-backed environment against a launched simulator: a private ROS master on a random port
# (private_roscore.sh), occlusion_sim under the namespace /python_test with sim.yaml at 64 px,
# then test_ros_env.py.
# Usage: ros_env_test.sh DEVEL_SETUP_BASH SOURCE_DIR
set -eo pipefail
setup=${1:?usage: ros_env_test.sh DEVEL_SETUP_BASH SOURCE_DIR}
source_dir=${2:?usage: ros_env_test.sh DEVEL_SETUP_BASH SOURCE_DIR}
source "$source_dir/test/private_roscore.sh" "$setup"
rosparam load "$source_dir/config/sim.yaml" /python_test/occlusion_sim
rosparam set /python_test/occlusion_sim/width 64
rosparam set /python_test/occlusion_sim/height 64
ROS_NAMESPACE=/python_test "$bin/occlusion_sim" __name:=occlusion_sim >/dev/null 2>&1 &
pids+=($!)
export OCCLUSION_TEST_NAMESPACE=/python_test
export PYTHONDONTWRITEBYTECODE=1
/usr/bin/python3 -m pytest -q -p no:cacheprovider "$source_dir/test/python/test_ros_env.py"
