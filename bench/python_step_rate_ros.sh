#!/usr/bin/env bash
# bench/python_step_rate.py with a simulator node at the same size on a private ROS master, so
# the table also holds the ROS-backed environment's rate.
# Usage: bash bench/python_step_rate_ros.sh [python_step_rate.py arguments]
set -eo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
size=256
for ((i = 1; i <= $#; i++)); do
  if [[ ${!i} == --size ]]; then j=$((i + 1)); size=${!j}; fi
done
source "$here/test/private_roscore.sh" "$here/.build_ws/devel/setup.bash"
rosparam load "$here/config/sim.yaml" /bench/occlusion_sim
rosparam set /bench/occlusion_sim/width "$size"
rosparam set /bench/occlusion_sim/height "$size"
rosparam set /bench/occlusion_sim/max_steps 100
ROS_NAMESPACE=/bench "$bin/occlusion_sim" __name:=occlusion_sim >/dev/null 2>&1 &
pids+=($!)
/usr/bin/python3 "$here/bench/python_step_rate.py" --ros-namespace /bench "$@"
