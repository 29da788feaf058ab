#!/usr/bin/env bash
# Fails if the ROS-free core library reaches any ROS or libtorch header, directly or through
# another header, or if its compile commands carry a catkin/ROS include path. The core is the
# module folders listed in core_modules (src/<module>/ and include/occlusion_env/<module>/).
# Usage: check_core_boundary.sh SOURCE_DIR COMPILE_COMMANDS_JSON
set -uo pipefail
src=${1:?source dir}
db=${2:?compile_commands.json}
ros_dirs='/(ros|roscpp|rosconsole|sensor_msgs|geometry_msgs|std_msgs|tf2_ros|tf2_msgs|cv_bridge|image_transport|visualization_msgs|xmlrpcpp|torch|ATen|c10)/'
status=0
core_modules=(common geometry scene render sensor occlusion env agents)
core_dirs=()
for module in "${core_modules[@]}"; do
  core_dirs+=("$src/src/$module" "$src/include/occlusion_env/$module")
done

# 1. Direct includes.
if grep -rnE '#\s*include\s*[<"](ros|sensor_msgs|geometry_msgs|std_msgs|tf2_ros|cv_bridge|image_transport|visualization_msgs|torch|ATen|occlusion_env/(ros|eval|learning))/' \
    "${core_dirs[@]}"; then
  echo "core_boundary: the core includes ROS, libtorch or non-core headers (above)"; status=1
fi

# 2. Transitive includes and include paths, from the compiler itself.
n=0
while IFS= read -r entry; do
  file=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["file"])' "$entry")
  cmd=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["command"])' "$entry")
  if grep -qE -- '-I[^ ]*(devel/include|/opt/ros)' <<<"$cmd"; then
    echo "core_boundary: $file is compiled with a catkin include path"; status=1
  fi
  # Preprocess only, listing every header reached.
  deps_cmd=$(sed -E 's/ -o [^ ]+/ /; s/ -c / /' <<<"$cmd")
  deps=$(cd "$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["directory"])' "$entry")" && eval "$deps_cmd -M -MF /dev/stdout" 2>&1)
  if grep -qE "$ros_dirs" <<<"$deps"; then
    echo "core_boundary: $file reaches ROS headers:"; grep -oE "[^ ]*$ros_dirs[^ ]*" <<<"$deps" | head -5
    status=1
  fi
  n=$((n + 1))
done < <(python3 - "$db" "$src" "${core_modules[@]}" <<'PY'
import json, os, sys
db, src, modules = sys.argv[1], os.path.realpath(sys.argv[2]), sys.argv[3:]
core = tuple(os.path.join(src, "src", m) + os.sep for m in modules)
for e in json.load(open(db)):
    if os.path.realpath(e["file"]).startswith(core):
        print(json.dumps(e))
PY
)
if [[ $n -eq 0 ]]; then echo "core_boundary: no core sources in $db"; status=1; fi
[[ $status -eq 0 ]] && echo "core_boundary: $n core sources checked, no ROS or libtorch header reached"
exit $status
