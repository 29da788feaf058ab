#!/usr/bin/env bash
# The short form of the service benchmark: the simulator and occlusion_service_bench started
# together (the benchmark must wait for every service it uses), three times in a row; each run
# must exit 0 and print its table. Uses a private ROS master on a random port.
# Usage: service_bench_short.sh DEVEL_SETUP_BASH SOURCE_DIR
set -eo pipefail
setup=${1:?usage: service_bench_short.sh DEVEL_SETUP_BASH SOURCE_DIR}
source_dir=${2:?usage: service_bench_short.sh DEVEL_SETUP_BASH SOURCE_DIR}
source "$(dirname "${BASH_SOURCE[0]}")/private_roscore.sh" "$setup"
for run in 1 2 3; do
  rosparam load "$source_dir/config/sim.yaml" /occlusion_sim
  rosparam set /occlusion_sim/width 128
  rosparam set /occlusion_sim/height 128
  rosparam set /occlusion_sim/start_seed 1
  "$bin/occlusion_sim" __name:=occlusion_sim >/dev/null 2>&1 &
  sim=$!
  pids+=($sim)
  # Started at the same moment as the simulator, as roslaunch does.
  out=$("$bin/occlusion_service_bench" __name:=occlusion_service_bench _steps:=100 2>&1) || {
    echo "service_bench_short: run $run failed:"; echo "$out"; exit 1; }
  echo "$out" | grep -q "ROS overhead" || {
    echo "service_bench_short: run $run printed no table:"; echo "$out"; exit 1; }
  echo "run $run: $(echo "$out" | grep 'ROS overhead')"
  kill "$sim"; wait "$sim" 2>/dev/null || true
  rosparam delete /occlusion_sim
done
echo "service_bench_short: 3 runs printed their table"
