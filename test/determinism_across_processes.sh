#!/usr/bin/env bash
# Determinism as a contract: the same seed and the same actions give bit-identical observations
# and rewards in two separate processes. Runs occlusion_render twice (reset + 10 steps) and
# compares every image byte for byte and every printed figure.
# Usage: determinism_across_processes.sh OCCLUSION_RENDER
set -euo pipefail
render=${1:?usage: determinism_across_processes.sh OCCLUSION_RENDER}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for run in a b; do
  "$render" --seed 4242 --size 128 --steps 10 --action 0.3,1 --out "$work/$run" >"$work/$run.txt"
done
status=0
for image in rgb depth occlusion instance; do
  cmp -s "$work/a/$image.png" "$work/b/$image.png" || { echo "differs: $image.png"; status=1; }
done
# The printed figures, minus the line naming the output folder.
diff <(grep -v '^wrote' "$work/a.txt") <(grep -v '^wrote' "$work/b.txt") || status=1
grep -q '^step 10: reward' "$work/a.txt" || { echo "expected 10 steps:"; cat "$work/a.txt"; status=1; }
exit $status
