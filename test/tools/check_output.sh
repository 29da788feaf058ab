#!/usr/bin/env bash
# occlusion_train --check writes its figures where --out says, and a file it cannot write (a
# folder that is not there) stops it with an error naming the file, not a result that went nowhere.
# Usage: check_output.sh BIN_DIR SOURCE_DIR
set -euo pipefail
bin=${1:?usage: check_output.sh BIN_DIR SOURCE_DIR}
source_dir=${2:?usage: check_output.sh BIN_DIR SOURCE_DIR}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin/occlusion_dataset" --out "$work/frames" --scenes 2 --frames 2 --first-seed 960000 --size 64 \
    --no-oracle --validation 0 --threads 1 > /dev/null 2>&1
model="$source_dir/models/multitask_unet64.pt"
"$bin/occlusion_train" --check "$model" --data "$work/frames" --threads 1 --out "$work/check.json" \
    > "$work/said.txt" 2>&1
/usr/bin/python3 - "$work/check.json" <<'PY'
import json, sys
figures = json.load(open(sys.argv[1]))
assert 0.0 <= figures["figures"]["val_iou"] <= 1.0, figures["figures"]
PY
code=0
said=$("$bin/occlusion_train" --check "$model" --data "$work/frames" --threads 1 \
    --out "$work/no_such_folder/check.json" 2>&1) || code=$?
if [[ $code == 0 || $said != *"cannot write $work/no_such_folder/check.json"* ]]; then
  echo "check_output: --out into a missing folder gave exit code $code: $said"
  exit 1
fi
echo "check_output: --check writes its JSON to --out, and an unwritable --out is an error naming it"
