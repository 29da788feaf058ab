#!/usr/bin/env bash
# The short form of the ROS soak: 3,000 steps through the simulator's services (128x128, a reset
# every 50 steps); fails when the simulator's memory grows more than 5 MiB after warm-up, the step
# rate decays, or a request fails. Uses a private ROS master on a random port.
# Usage: service_soak_short.sh DEVEL_SETUP_BASH SOURCE_DIR
set -eo pipefail
setup=${1:?usage: service_soak_short.sh DEVEL_SETUP_BASH SOURCE_DIR}
source_dir=${2:?usage: service_soak_short.sh DEVEL_SETUP_BASH SOURCE_DIR}
source "$(dirname "${BASH_SOURCE[0]}")/private_roscore.sh" "$setup"
rosparam load "$source_dir/config/sim.yaml" /occlusion_sim
rosparam set /occlusion_sim/width 128
rosparam set /occlusion_sim/height 128
"$bin/occlusion_sim" __name:=occlusion_sim >/dev/null 2>&1 &
pids+=($!)
"$bin/occlusion_service_soak" __name:=occlusion_service_soak _steps:=3000 \
  _warmup:=1000 _report_every:=1000 _check:=true
