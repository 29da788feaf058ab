#!/usr/bin/env bash
# Regenerates EVALUATION.md and its tables and plots from scratch: both 50-scene held-out sets
# (Table 4/5 layouts) and the two start-azimuth sweeps (Figure 5), with CSVs and PNGs in
# doc/evaluation/. Needs the built workspace (make build), jags and python3-matplotlib.
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
exec "$evaluator" --all --out "$out" --report "$report" --source-dir "$root" "$@"
