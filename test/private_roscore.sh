# Sourced by the shell tests that need a ROS master of their own: sources the workspace's setup
# script ($1), starts roscore on a free random port with its own log folder, and stops everything
# put in `pids` (and the master) on exit. Sets `bin` to the workspace's executables.
# A master that dies at start (its port taken between the check and the bind) is started again on
# another port; one that does not answer within 60 s fails the test with roscore's own output.
source "${1:?private_roscore.sh: give the devel/setup.bash of the workspace}"
export ROS_LOG_DIR=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$ROS_LOG_DIR"
}
trap cleanup EXIT

# True when something already listens on localhost:$1.
port_in_use() { (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }

master_up=false
for attempt in 1 2 3; do
  port=$((20000 + RANDOM % 20000))
  while port_in_use "$port"; do port=$((20000 + RANDOM % 20000)); done
  export ROS_MASTER_URI=http://localhost:$port
  roscore -p "$port" >"$ROS_LOG_DIR/roscore_$attempt.out" 2>&1 &
  master=$!
  pids+=($master)
  # rosparam's own start-up takes ~0.3 s, so this waits up to about a minute.
  for _ in $(seq 120); do
    if rosparam list >/dev/null 2>&1; then master_up=true; break; fi
    kill -0 "$master" 2>/dev/null || break
    sleep 0.2
  done
  $master_up && break
  echo "private_roscore.sh: the master on port $port did not answer (attempt $attempt):" >&2
  cat "$ROS_LOG_DIR/roscore_$attempt.out" >&2
  kill "$master" 2>/dev/null || true
done
$master_up || { echo "private_roscore.sh: no ROS master after 3 attempts" >&2; exit 1; }
bin=$(dirname "$1")/lib/occlusion_env
