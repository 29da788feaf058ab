#!/usr/bin/env bash
# Trains the five network variants of the paper's Table 3 (UNet, R-UNet, SR-UNet, SAR-UNet,
# SAR-UNet-L1) on the same data, at the same resolution, for the same number of epochs, one
# libtorch thread each, and copies each run's best-model manifest and log into doc/training/
# (<variant>_<size>px.json / .csv / .png), where `occlusion_eval --all` reads them for
# EVALUATION.md's Table 3. Runs resume: re-run the same command after an interruption.
#
# Usage: scripts/train_table3.sh [DATA_DIR] [RUNS_DIR]
#   DATA_DIR  default data/train_sweethome3d (made by the occlusion_dataset command in doc/TRAINING.md)
#   RUNS_DIR  default runs (checkpoints and logs; not in git)
# Environment: SIZE (network input [px], default 64), EPOCHS (default 10), JOBS (variants trained
# at once, default 1; each uses one thread), VARIANTS (default all five, space-separated names),
# BCE (default 0: the paper's loss; X adds X times a pixel-wise binary cross-entropy on the
# occlusion map, and the runs are named <variant>_bce<X>), EXTRA_DATA (further datasets, passed
# as more --data options: their training scenes are added) with TAG (appended to the run names),
# MAX_SCENES (only the first N scenes of each dataset; default all), INIT_FROM (a model to start
# from instead of random weights, a warm restart, passed as --init-from; needs a TAG; only with
# one variant, the model's), LR (AdamW's peak learning rate; default the trainer's, 0.001).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
data="${1:-$root/data/train_sweethome3d}"
runs="${2:-$root/runs}"
size="${SIZE:-64}"
epochs="${EPOCHS:-10}"
jobs="${JOBS:-1}"
bce="${BCE:-0}"
extra_data="${EXTRA_DATA:-}"
tag="${TAG:-}"
max_scenes="${MAX_SCENES:-0}"
init_from="${INIT_FROM:-}"
learning_rate="${LR:-}"
[[ -z "$extra_data" || -n "$tag" ]] || { echo "train_table3: EXTRA_DATA needs a TAG" >&2; exit 1; }
variants="${VARIANTS:-unet r_unet sr_unet sar_unet sar_unet-L1}"
[[ -z "$init_from" || -n "$tag" ]] || { echo "train_table3: INIT_FROM needs a TAG" >&2; exit 1; }
[[ -z "$init_from" || "$(wc -w <<<"$variants")" == 1 ]] ||
  { echo "train_table3: INIT_FROM needs one variant (VARIANTS=...)" >&2; exit 1; }
trainer="$root/.build_ws/devel/lib/occlusion_env/occlusion_train"
[[ -x "$trainer" ]] || { echo "train_table3: $trainer not built (make build)" >&2; exit 1; }
[[ -d "$data" ]] || { echo "train_table3: no dataset at $data (see doc/TRAINING.md, "Training data")" >&2; exit 1; }
mkdir -p "$runs" "$root/doc/training"
# From the source tree, with paths relative to it (as the manifests record them).
data="$(realpath --relative-to="$root" "$data")"
runs="$(realpath --relative-to="$root" "$runs")"
relative_extra=""
for dir in $extra_data; do relative_extra+=" $(realpath --relative-to="$root" "$dir")"; done
extra_data="$relative_extra"
[[ -z "$init_from" ]] || init_from="$(realpath --relative-to="$root" "$init_from")"
cd "$root"

# One variant: its command, run to the end (resuming), then its results copied into doc/training.
train_one() {
  local name=$1 variant=${1%-L1} loss=mse
  [[ "$name" == *-L1 ]] && loss=smooth_l1
  local extra=()
  if [[ "$bce" != 0 ]]; then
    name="${name}_bce${bce}"
    extra=(--bce-weight "$bce")
  fi
  local dir
  for dir in $extra_data; do
    extra+=(--data "$dir")
  done
  [[ "$max_scenes" != 0 ]] && extra+=(--max-scenes "$max_scenes")
  [[ -n "$init_from" ]] && extra+=(--init-from "$init_from")
  [[ -n "$learning_rate" ]] && extra+=(--lr "$learning_rate")
  [[ -n "$tag" ]] && name="${name}_${tag}"
  local run="$runs/table3_${name}_${size}"
  local args=(--data "$data" --out "$run" --variant "$variant" --size "$size" --epochs "$epochs"
    --direction-loss "$loss" "${extra[@]}" --threads 1)
  local command="occlusion_train ${args[*]}"
  echo "train_table3: $name: $command (log: $run.log)"
  "$trainer" "${args[@]}" >"$run.log" 2>&1 ||
    { echo "train_table3: $name failed, see $run.log" >&2; return 1; }
  python3 "$root/scripts/record_run.py" "$run" "$root/doc/training/${name}_${size}px" "$command"
  echo "train_table3: $name done: $(tail -n 1 "$run.log")"
}
export -f train_one
export runs size epochs data root trainer bce extra_data tag max_scenes init_from learning_rate
printf '%s\n' $variants | xargs -P "$jobs" -I{} bash -c 'train_one {}'
/usr/bin/python3 "$root/scripts/plot_table3.py" "$root/doc/training" ||
  echo "train_table3: plotting failed (python3-matplotlib?)" >&2
