#!/usr/bin/env bash
# Run by install_space.sh inside its own mount namespace with a clean environment: hides the
# given folders, sources only the install space, then runs the learned agent, an evaluation with
# its plot and demo.launch from it, and checks the scripts the launch files run are there.
# Usage: run_installed.sh INSTALL_SPACE WORK_DIR HIDDEN_DIR...
set -euo pipefail
install=${1:?usage: run_installed.sh INSTALL_SPACE WORK_DIR HIDDEN_DIR...}
work=${2:?}
shift 2
for hidden in "$@"; do
  [[ -d "$hidden" ]] || continue  # inside a folder hidden already
  mount -t tmpfs -o size=1m tmpfs "$hidden"
  if [[ -n "$(ls -A "$hidden")" ]]; then echo "install_space: $hidden is not hidden"; exit 1; fi
done
mkdir -p "$work" "$HOME"
cd "$work"
set +u  # the ROS setup scripts read unset variables
source "$install/setup.bash"
set -u
export ROS_HOME=$work/ros_home ROS_LOG_DIR=$work/ros_log
share=$(rospack find occlusion_env)
if [[ "$share" != "$install/share/occlusion_env" ]]; then
  echo "install_space: rospack finds occlusion_env at $share, not in the install space"; exit 1
fi
echo "install_space: rospack find occlusion_env -> $share"

# 1. The learned agent (its model from the share directory) on two scenes.
out=$(rosrun occlusion_env occlusion_agents --agents predicted_escape --scenes 2 --size 128 2>&1) ||
  { echo "$out"; echo "install_space: occlusion_agents failed"; exit 1; }
echo "$out"
grep -qE '^ *predicted_escape ' <<<"$out" ||
  { echo "install_space: no predicted_escape row in occlusion_agents' table"; exit 1; }

# 2. An evaluation of two scenes of a shipped scene set: the episode CSV, BEST and the plots that
#    scripts/plot_evaluation.py (found in the share directory) draws.
rosrun occlusion_env occlusion_eval --scenes "$share/config/scenes/test_embedded.yaml" --limit 2 \
  --agents predicted_escape,random --best-samples 200 --out "$work/eval" > eval.log 2>&1 ||
  { cat eval.log; echo "install_space: occlusion_eval failed"; exit 1; }
plots=$(find "$work/eval" -name '*.png' | wc -l)
if [[ $plots -eq 0 ]]; then
  cat eval.log; ls -R "$work/eval"; echo "install_space: the evaluation drew no plot"; exit 1
fi
echo "install_space: occlusion_eval wrote $(ls "$work/eval" | wc -l) files, $plots plots"

# 3. Every script an installed launch file runs from the share directory is there.
for launch in "$share"/launch/*.launch; do
  while read -r script; do
    [[ -x "$share/$script" ]] ||
      { echo "install_space: $(basename "$launch") runs $script: not in the install space"; exit 1; }
  done < <(grep -o 'find occlusion_env)/scripts/[A-Za-z0-9_.]*' "$launch" | cut -d/ -f2- | sort -u)
done
echo "install_space: the scripts the launch files run are installed"

# 4. demo.launch with the learned agent, on a private master; it ends with the agent.
port=$((20000 + RANDOM % 20000))
export ROS_MASTER_URI=http://localhost:$port
timeout 300 roslaunch -p "$port" --screen occlusion_env demo.launch agent:=predicted_escape \
  episodes:=2 csv:="$work/demo_episodes.csv" > demo.log 2>&1 || true
if ! grep -q "predicted_escape agent done" demo.log; then
  tail -30 demo.log; echo "install_space: demo.launch did not finish"; exit 1
fi
grep -E "episode [0-9]+/[0-9]+ seed|agent done" demo.log | sed -E 's/^.*\]: //; s/\x1b\[[0-9;]*m//g'
rows=$(($(wc -l < demo_episodes.csv) - 1))
[[ $rows -eq 2 ]] || { echo "install_space: $rows episodes in demo.launch's CSV, not 2"; exit 1; }
echo "install_space: the install space alone ran the learned agent, a plot and demo.launch"
