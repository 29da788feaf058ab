#!/usr/bin/env bash
# Runs every test registered with CTest (gtests and rostests) and fails if any fails.
# catkin_make run_tests would exit 0 on failures, so CTest's exit status is what counts here.
set -uo pipefail
build_dir=${1:?usage: run_tests.sh BUILD_DIR}
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
set +u  # the ROS setup scripts read unset variables
source "$build_dir/../devel/setup.bash"
set -u
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}
cd "$build_dir"
rm -rf test_results/occlusion_env
ctest --output-on-failure --timeout 900 "${@:2}"
status=$?
# Belt and braces: a test binary can exit 0 yet record failures in its XML.
if ! catkin_test_results test_results >/dev/null 2>&1; then
  catkin_test_results test_results
  status=1
fi
exit $status
