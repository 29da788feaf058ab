#!/usr/bin/env bash
# occlusion_bridge_calibration --views-csv: one row per view (the start view and one per step),
# and the rules the tool prints follow from those rows; two workers give the same; a second
# opinion joins its map.
set -euo pipefail
tool=${1:?usage: bridge_calibration_views.sh TOOL SOURCE_DIR}
source_dir=${2:?usage: bridge_calibration_views.sh TOOL SOURCE_DIR}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$tool" --model "$source_dir/models/multitask_unet64.pt" --scenes 3 --max-steps 4 --size 64 \
    --probabilities 0.2,0.5 --thresholds 0,64 --confirm-views 1,2 --threads 1 \
    --views-csv "$work/views.csv" > "$work/table.md" 2> "$work/progress.txt"
# Two workers share the scenes out: the same views and table, in the same order.
"$tool" --model "$source_dir/models/multitask_unet64.pt" --scenes 3 --max-steps 4 --size 64 \
    --probabilities 0.2,0.5 --thresholds 0,64 --confirm-views 1,2 --threads 2 \
    --views-csv "$work/views2.csv" > "$work/table2.md" 2> "$work/progress2.txt"
cmp "$work/views.csv" "$work/views2.csv"
cmp "$work/table.md" "$work/table2.md"
/usr/bin/python3 - "$work/views.csv" "$work/table.md" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert list(rows[0].keys()) == ["seed", "step", "true_px", "estimated_px_at_0.2",
                                "estimated_px_at_0.5"], list(rows[0].keys())
assert len(rows) == 3 * 5, len(rows)  # 3 scenes x (the start view + 4 steps)
assert [r["seed"] for r in rows[::5]] == ["900000", "900001", "900002"]
assert [int(r["step"]) for r in rows[:5]] == [0, 1, 2, 3, 4]
paths = [rows[i:i + 5] for i in range(0, 15, 5)]

# Each printed rule, recomputed from the rows: the stop is the step whose view is the
# confirm-th in a row at or below the threshold, the start view never counting.
printed = {}
for line in open(sys.argv[2]):
    cells = [c.strip() for c in line.strip().strip("|").split("|")]
    if len(cells) == 7 and cells[0] in ("0.2", "0.5"):
        printed[(cells[0], int(cells[1]), int(cells[2]))] = (int(cells[3]), int(cells[5]),
                                                             cells[6])
assert len(printed) == 8, printed
for (p, threshold, confirm), (clear, never, mean_steps) in printed.items():
    want_clear = want_never = steps = 0
    for path in paths:
        run, stop = 0, None
        for t in range(1, 5):
            run = run + 1 if int(path[t]["estimated_px_at_" + p]) <= threshold else 0
            if run >= confirm:
                stop = t
                break
        steps += 4 if stop is None else stop
        if stop is None:
            want_never += 1
        elif int(path[stop]["true_px"]) == 0:
            want_clear += 1
    assert (clear, never, mean_steps) == (want_clear, want_never, "%.1f" % (steps / 3)), (
        p, threshold, confirm, clear, never, mean_steps)
print("bridge_calibration_views: 15 views, 8 rules agree")
PY

# A second opinion (--second-model, as the bridge's ~second_model) joins its map to each
# probability's: the same network at 0.2 leaves the counts at 0.2 as they were and makes those at
# 0.5 the counts at 0.2 (a pixel above 0.5 is above 0.2).
"$tool" --model "$source_dir/models/multitask_unet64.pt" --scenes 3 --max-steps 4 --size 64 \
    --probabilities 0.2,0.5 --thresholds 0 --confirm-views 1 \
    --second-model "$source_dir/models/multitask_unet64.pt" --second-probability 0.2 \
    --views-csv "$work/joined.csv" > "$work/joined.md" 2> "$work/progress.txt"
grep -q "^joined by: .*multitask_unet64.pt at probability 0.2" "$work/joined.md"
/usr/bin/python3 - "$work/views.csv" "$work/joined.csv" <<'PY'
import csv, sys
alone = list(csv.DictReader(open(sys.argv[1])))
joined = list(csv.DictReader(open(sys.argv[2])))
assert [r["true_px"] for r in joined] == [r["true_px"] for r in alone], "other paths"
assert [r["estimated_px_at_0.2"] for r in joined] == [r["estimated_px_at_0.2"] for r in alone]
assert [r["estimated_px_at_0.5"] for r in joined] == [r["estimated_px_at_0.2"] for r in alone]
# Not trivially: the map differs between the two probabilities somewhere.
assert any(r["estimated_px_at_0.5"] != r["estimated_px_at_0.2"] for r in alone), "a flat map"
print("bridge_calibration_views: the second opinion joins its map")
PY
if "$tool" --model "$source_dir/models/multitask_unet64.pt" --scenes 1 --second-probability 0.3 \
    > /dev/null 2>&1; then
  echo "bridge_calibration_views: --second-probability without --second-model was accepted" >&2
  exit 1
fi
