#!/usr/bin/env bash
# occlusion_dataset end to end on a tiny dataset: generate, resume, refuse other options, audit.
# Usage: dataset_tool_tiny.sh OCCLUSION_DATASET
set -euo pipefail
tool=${1:?usage: dataset_tool_tiny.sh OCCLUSION_DATASET}
dir=$(mktemp -d)/tiny
trap 'rm -rf "$(dirname "$dir")"' EXIT
"$tool" --out "$dir" --scenes 3 --frames 4 --size 64
out=$("$tool" --out "$dir" --scenes 3 --frames 4 --size 64)
echo "$out"
grep -q "3 complete already" <<<"$out" || { echo "dataset_tool_tiny: no resume"; exit 1; }
if "$tool" --out "$dir" --scenes 3 --frames 5 --size 64 2>err.log; then
  echo "dataset_tool_tiny: other options were accepted"; exit 1
fi
grep -q "other options" err.log || { cat err.log; exit 1; }
rm -f err.log
"$tool" --audit "$dir" --samples 12
ls "$dir/train/000000/rgb" | head -2
