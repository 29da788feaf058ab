#!/usr/bin/env bash
# The evaluation's episodes through ROS: runs every agent of an in-process episode CSV that can
# run over ROS (all but the oracle, which reads the scene) as an agent node against the simulator
# node (agent.launch, on a private ROS master) on the same scene set, and compares each agent's
# episodes with its in-process ones, column by column (scripts/compare_episode_csvs.py: steps,
# success, the whole path, final occlusion; not wall time). Exits 1 on any difference. With
# REPORT, appends a line saying what was checked to it (scripts/evaluate.sh passes EVALUATION.md).
# Usage: scripts/check_through_ros.sh SCENE_SET.yaml IN_PROCESS_EPISODES.csv [REPORT]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
scenes=$(realpath "${1:?usage: check_through_ros.sh SCENE_SET.yaml EPISODES.csv [REPORT]}")
episodes=$(realpath "${2:?usage: check_through_ros.sh SCENE_SET.yaml EPISODES.csv [REPORT]}")
report="${3:-}"
work=$(mktemp -d)
source_of() { sed -n "s/^$1: *\([a-z0-9_]*\).*/\1/p" "$scenes"; }
object_source=$(source_of source)
model_split=$(source_of model_split)
model_split=${model_split:-all}
agents=$(python3 -c "
import csv, sys
seen = []
for row in csv.DictReader(open(sys.argv[1])):
    if row['agent'] != 'oracle' and row['agent'] not in seen:
        seen.append(row['agent'])
print(' '.join(seen))" "$episodes")
set +u  # ROS's setup scripts read unset variables
source "$root/test/private_roscore.sh" "$root/.build_ws/devel/setup.bash"
set -u
failed=0
checked=0
for agent in $agents; do
  python3 - "$episodes" "$agent" "$work/$agent.in_process.csv" <<'PY'
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["agent"] == sys.argv[2]]
with open(sys.argv[3], "w", newline="") as f:
    writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    writer.writeheader()
    writer.writerows(rows)
PY
  echo "check_through_ros: $agent through the simulator and agent nodes..."
  roslaunch occlusion_env agent.launch agent:="$agent" scene_set:="$scenes" \
      object_source:="$object_source" model_split:="$model_split" csv:="$work/$agent.ros.csv" \
      >"$work/$agent.log" 2>&1 || { echo "check_through_ros: $agent's launch failed:"; tail -20 "$work/$agent.log"; failed=1; continue; }
  if python3 "$root/scripts/compare_episode_csvs.py" "$work/$agent.in_process.csv" "$work/$agent.ros.csv"; then
    checked=$((checked + $(($(wc -l < "$work/$agent.ros.csv") - 1))))
  else
    failed=1
  fi
done
set_name=$(basename "$scenes" .yaml)
if [[ $failed -eq 0 ]]; then
  line="**Checked through ROS** by \`scripts/check_through_ros.sh\` (run by \`scripts/evaluate.sh\`): $checked episodes of \`$set_name\` ($agents), each run through the simulator node and the agent node, equal their in-process episodes above in every column but wall time."
  echo "check_through_ros: $line"
  [[ -n "$report" ]] && printf '\n%s\n' "$line" >> "$report"
fi
rm -rf "$work"
exit $failed
