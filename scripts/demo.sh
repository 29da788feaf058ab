#!/usr/bin/env bash
# The main job on the embedded objects:
#  1. occlusion_render draws three seeded scenes to ${DEMO_OUT:-output/demo}/seed_<N>/ (images);
#  2. roslaunch runs the simulator node with the gradient agent node (demo.launch) on the same
#     seeds: the agent resets each scene through /occlusion/reset, steps along the negative
#     occlusion gradient (/occlusion/get_occlusion_gradient) through /occlusion/step until no
#     object hides another, and prints each episode; then the same with the learned
#     predicted-escape agent, which sees only the RGB-D image; then that agent once more through
#     the camera bridge, in front of the simulator standing in for a real camera and robot
#     (doc/CAMERA_BRIDGE.md). roslaunch ends with the agent.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
set +u  # the ROS setup scripts read unset variables
source .build_ws/devel/setup.bash
set -u
out=${DEMO_OUT:-output/demo}
for seed in 1 2 3; do
  echo "== scene seed $seed (occlusion_render) =="
  .build_ws/devel/lib/occlusion_env/occlusion_render --seed "$seed" --out "$out/seed_$seed"
done
echo "Open $out/seed_1/occlusion.png to see the occluded pixels (red) and each object's outline."

# A private master on its own port, so that a roscore already running is left alone.
export ROS_MASTER_URI=http://localhost:${DEMO_ROS_PORT:-11411}
mkdir -p "$out"
out_abs=$(cd "$out" && pwd)
export ROS_LOG_DIR=${ROS_LOG_DIR:-$out_abs/ros_log}
# The simulator's gradient agent, then the learned agent that sees only the RGB-D image (the
# shipped model, models/multitask_unet64.pt), on the same scenes.
for run in gradient predicted_escape predicted_escape:camera_bridge; do
  agent=${run%%:*}
  bridge=false
  [[ "$run" == *:camera_bridge ]] && bridge=true
  name=${run/:/_}
  echo "== the $agent agent on the same scenes$([[ $bridge == true ]] && echo " through the camera bridge") (roslaunch occlusion_env demo.launch agent:=$agent camera_bridge:=$bridge) =="
  log=$out/demo_${name}_launch.log
  csv=$out_abs/${name}_episodes.csv
  roslaunch -p "${DEMO_ROS_PORT:-11411}" --screen occlusion_env demo.launch agent:="$agent" \
    camera_bridge:="$bridge" episodes:=3 seed:=1 csv:="$csv" > "$log" 2>&1 || true
  # The agent's report; the whole launch output stays in $log.
  if ! grep -q "$agent agent done" "$log"; then
    echo "demo: the $agent agent did not finish; see $log" >&2
    tail -20 "$log" >&2
    exit 1
  fi
  grep -E "episode [0-9]+/[0-9]+ seed|agent done" "$log" | sed -E 's/^.*\]: //; s/\x1b\[[0-9;]*m//g'
  if [[ $bridge == true ]]; then
    echo "(Through the bridge, 'unoccluded' and the occlusion are the network's estimate, as a real"
    echo " camera allows; test/ros/camera_bridge.test checks them against the stand-in's truth.)"
  fi
  echo "Episodes (steps, success, final occlusion, camera path): $csv"
  echo "Full launch output: $log"
done
