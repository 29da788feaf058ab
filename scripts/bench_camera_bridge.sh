#!/usr/bin/env bash
# The camera bridge's own cost per step: the simulator stands in for the camera and robot
# (~mode camera), the predicted_escape agent node runs EPISODES episodes through the bridge, and
# the bridge logs, every 20 steps, the median of its own work per step (goal, pose, conversion,
# the occlusion estimate) apart from the waits for the robot and for the first frame after
# arrival. Needs the built workspace (make build). BENCHMARKS.md quotes its output.
# Usage: scripts/bench_camera_bridge.sh [EPISODES] [CAMERA_RATE_HZ] [MOTION_TIME_S] [MODEL]
#   MODEL: the bridge's network (default: the shipped one); "none": no estimate (episodes then
#   run to max_steps, since nothing says the view is clear)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
episodes=${1:-20}
camera_rate=${2:-30}
motion_time=${3:-0.05}
model=${4:-$root/models/multitask_unet64.pt}
set +u
source "$root/test/private_roscore.sh" "$root/.build_ws/devel/setup.bash"
set -u
log=$(mktemp)
roslaunch occlusion_env camera_bridge.launch stand_in:=true object_source:=sweethome3d \
  camera_rate:="$camera_rate" motion_time:="$motion_time" model:="$model" >"$log" 2>&1 &
pids+=($!)
echo "bench_camera_bridge: $episodes episodes of predicted_escape through the bridge" \
     "(Sweet Home 3D, 256 px, camera $camera_rate Hz, robot motion $motion_time s," \
     "estimate: $model)"
roslaunch occlusion_env agent.launch sim:=false agent:=predicted_escape seed:=1001000 \
  episodes:="$episodes" csv:="$(mktemp -d)/bridge.csv" 2>&1 | grep -a "done:" |
  sed 's/^.*\]: //; s/\x1b\[0m//g' || true
sleep 1  # rosout writes its log file
grep -ah "median of the last" "$ROS_LOG_DIR"/latest/rosout.log |
  sed 's/^.*camera bridge, //'
rm -f "$log"
