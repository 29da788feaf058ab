# Sourced by the shell tests that need a ROS master of their own: sources the workspace's setup
# script ($1), starts roscore on a random port with its own log folder, and stops everything put
# in `pids` (and the master) on exit. Sets `bin` to the workspace's executables.
source "${1:?private_roscore.sh: give the devel/setup.bash of the workspace}"
port=$((20000 + RANDOM % 20000))
export ROS_MASTER_URI=http://localhost:$port
export ROS_LOG_DIR=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$ROS_LOG_DIR"
}
trap cleanup EXIT
roscore -p "$port" >/dev/null 2>&1 &
pids+=($!)
for _ in $(seq 100); do rosparam list >/dev/null 2>&1 && break; sleep 0.2; done
bin=$(dirname "$1")/lib/occlusion_env
