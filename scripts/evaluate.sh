#!/usr/bin/env bash
# Regenerates EVALUATION.md and its tables and plots from scratch: the held-out sets (Table 4/5
# layouts) and the two start-azimuth sweeps (Figure 5), with CSVs and PNGs in doc/evaluation/;
# then runs every agent but the oracle through the ROS nodes on test_sweethome3d and fails unless
# each episode equals its in-process run (scripts/check_through_ros.sh; a line in the report).
# Then appends the sections of doc/robustness/ (scripts/robustness.py), which it does not re-run.
# Needs the built workspace (make build), jags and python3-matplotlib.
# Usage: scripts/evaluate.sh [OUT_DIR] [extra occlusion_eval options, e.g. --agents random,gradient]
# With an OUT_DIR other than doc/evaluation, EVALUATION.md is left alone (the report goes to
# OUT_DIR/EVALUATION.md).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/doc/evaluation}"
shift || true
evaluator="$root/.build_ws/devel/lib/occlusion_env/occlusion_eval"
if [[ ! -x "$evaluator" ]]; then
  echo "evaluate.sh: $evaluator not built (make build)" >&2
  exit 1
fi
report="$root/EVALUATION.md"
[[ "$(realpath -m "$out")" == "$root/doc/evaluation" ]] || report="$out/EVALUATION.md"
rm -rf "$out"
mkdir -p "$out"
"$evaluator" --all --out "$out" --report "$report" --source-dir "$root" "$@"
"$root/scripts/check_through_ros.sh" "$root/config/scenes/test_sweethome3d.yaml" \
    "$out/test_sweethome3d_episodes.csv" "$report"
# Sections measured by their own, longer runs (the command that regenerates each is in it):
# doc/robustness/*.md.in, written by scripts/robustness.py --section.
for section in "$root"/doc/robustness/*.md.in; do
  [[ -f "$section" ]] || continue
  { echo; cat "$section"; } >> "$report"
done
