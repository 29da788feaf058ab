#!/usr/bin/env bash
# The main job on the embedded objects:
#  1. occlusion_render draws three seeded scenes to ${DEMO_OUT:-output/demo}/seed_<N>/ (images);
#  2. roslaunch runs the simulator node with occlusion_demo_client (demo.launch), which
#     resets the same seeds through the /occlusion/reset service, prints each scene's occlusion
#     figures and takes a few steps through /occlusion/step. roslaunch ends with the client.
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

echo "== the same scenes through the ROS node (roslaunch occlusion_env demo.launch) =="
# A private master on its own port, so that a roscore already running is left alone.
export ROS_MASTER_URI=http://localhost:${DEMO_ROS_PORT:-11411}
mkdir -p "$out"
export ROS_LOG_DIR=${ROS_LOG_DIR:-$(cd "$out" && pwd)/ros_log}
log=$out/demo_launch.log
roslaunch -p "${DEMO_ROS_PORT:-11411}" --screen occlusion_env demo.launch seeds:="[1, 2, 3]" \
  > "$log" 2>&1 || true
# The client's report; the whole launch output stays in $log.
if ! grep -q "^== scene seed" "$log"; then
  echo "demo: the ROS demo printed no scene; see $log" >&2
  tail -20 "$log" >&2
  exit 1
fi
sed -n '/^== scene seed\|^  /p' "$log"
echo "Full launch output: $log"
