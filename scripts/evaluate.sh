#!/usr/bin/env bash
# Regenerates the evaluation results and plots from scratch: the 50-scene embedded comparison
# (Table 4/5 layouts) and the two start-azimuth sweeps (Figure 5), written to doc/evaluation/
# (RESULTS.md, CSVs, PNGs). Needs the built workspace (catkin_make) and jags, python3-matplotlib.
# Usage: scripts/evaluate.sh [OUT_DIR] [extra occlusion_eval options, e.g. --agents random,gradient]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/doc/evaluation}"
shift || true
evaluator="$root/.build_ws/devel/lib/occlusion_env/occlusion_eval"
if [[ ! -x "$evaluator" ]]; then
  echo "evaluate.sh: $evaluator not built (make build)" >&2
  exit 1
fi
rm -rf "$out"
exec "$evaluator" --all --out "$out" --source-dir "$root" "$@"
