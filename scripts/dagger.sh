#!/usr/bin/env bash
# DAgger (doc/TRAINING.md, "DAgger"): rounds of (1) occlusion_dagger: the current model's
# predicted-escape agent rolled out on new training scenes, every state it visits labelled by
# the oracle, and (2) occlusion_train --init-from the current model on the base data plus every
# DAgger set so far, keeping every epoch's model; (3) the round's model chosen by the agent's mean
# steps on validation scenes (config/scenes/validation_sweethome3d_200.yaml, seeds 970000..,
# never trained on) among the round's start model and every epoch's: OUT/model_<k>/selection.csv,
# the chosen one copied to OUT/model_<k>/chosen.pt (its path in chosen.txt); it is the next round's agent. Every step
# resumes: re-run the same command after an interruption (finished work is skipped quickly).
#
# Usage: scripts/dagger.sh [BASE_DATA] [OUT]
#   BASE_DATA  default data/train_sweethome3d (the occlusion_dataset command in doc/TRAINING.md);
#              its validation scenes choose each round's best model
#   OUT        default runs/dagger: OUT/data_<k> (DAgger sets), OUT/model_<k> (training runs)
# Environment: MODEL (round 1's agent, default models/multitask_unet64.pt; the network, its
# variant, size and loss are taken from its manifest), ROUNDS (default 3), SCENES (roll-outs per
# round, default 1000), FIRST_SEED (default 100000; round k uses FIRST_SEED + (k-1) * SEED_STRIDE
# on, below the validation seeds 900,000 and away from the base data's), SEED_STRIDE (default
# 10000), BETA (per step, the probability of executing the oracle's move; default 0), SIZE
# (image size of the roll-outs and frames [px], default 128 as the base data), EPOCHS (per
# round, default 5), LR (per round, default the trainer's 1e-3), THREADS (roll-out workers,
# default 2), EXTRA_DATA (further datasets for every round's training, space-separated),
# VALIDATION (the scene set that chooses, default config/scenes/validation_sweethome3d_200.yaml:
# 200 scenes, since on 50 the rounds' models differ by less than the noise).
set -euo pipefail
shopt -s inherit_errexit  # a failure inside $(...) (choose_model's evaluations) stops the script
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
base="${1:-$root/data/train_sweethome3d}"
out="${2:-$root/runs/dagger}"
model="${MODEL:-$root/models/multitask_unet64.pt}"
rounds="${ROUNDS:-3}"
scenes="${SCENES:-1000}"
first_seed="${FIRST_SEED:-100000}"
stride="${SEED_STRIDE:-10000}"
beta="${BETA:-0}"
size="${SIZE:-128}"
epochs="${EPOCHS:-5}"
lr="${LR:-0.001}"
validation="${VALIDATION:-$root/config/scenes/validation_sweethome3d_200.yaml}"
threads="${THREADS:-2}"
extra_data="${EXTRA_DATA:-}"
bin="$root/.build_ws/devel/lib/occlusion_env"
for tool in occlusion_dagger occlusion_train occlusion_eval; do
  [[ -x "$bin/$tool" ]] || { echo "dagger.sh: $bin/$tool not built (make build)" >&2; exit 1; }
done
[[ -d "$base" ]] || { echo "dagger.sh: no base dataset at $base (doc/TRAINING.md)" >&2; exit 1; }
(( scenes <= stride )) || { echo "dagger.sh: SCENES ($scenes) > SEED_STRIDE ($stride)" >&2; exit 1; }
(( first_seed + rounds * stride <= 900000 )) ||
  { echo "dagger.sh: round seeds would reach the validation seeds (900000)" >&2; exit 1; }
mkdir -p "$out"
# From the source tree, with paths relative to it (as the training manifests record them).
relative() { realpath --relative-to="$root" "$1"; }
base="$(relative "$base")"
out="$(relative "$out")"
model="$(relative "$model")"
extra=()
for dir in $extra_data; do extra+=(--data "$(relative "$dir")"); done
cd "$root"

# The network and loss of a model, as occlusion_train flags (from its manifest).
network_flags() {
  python3 - "${1%.pt}.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
n, t = m["network"], m.get("training", {})
print(f"--variant {n['variant']} --size {n['input_size']} --base {n['base_channels']} "
      f"--direction-loss {t.get('direction_loss', 'mse')} --bce-weight {t.get('bce_weight', 0)}")
PY
}

# The predicted-escape agent of a model on the validation scenes: "mean_steps successes episodes"
# (failures counted at the step limit), from occlusion_eval's episode CSV (kept in $2).
validation_steps() {
  local csv="$2/$(basename "${validation%.yaml}")_episodes.csv"
  if [[ ! -s "$csv" ]]; then
    "$bin/occlusion_eval" --scenes "$validation" --agents predicted_escape --model "$1" \
      --out "$2" --no-plots >/dev/null
  fi
  python3 - "$csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
steps = [int(r["steps"]) for r in rows]
print(f"{sum(steps) / len(steps):.3f} {sum(int(r['success']) for r in rows)} {len(rows)}")
PY
}

# Chooses round $1's model: the start model or one of the run's epochs, whichever has the
# fewest mean steps on the validation scenes (ties: the earlier candidate); prints its path.
choose_model() {
  local run="$1/model_$2" start="$3" candidates=("$3") name result steps best="" best_steps=""
  for ((e = 1; e <= epochs; ++e)); do candidates+=("$run/epoch_$e.pt"); done
  echo "candidate,scene_set,mean_steps,successes,episodes" >"$run/selection.csv"
  for candidate in "${candidates[@]}"; do
    if [[ ! -f "$candidate" ]]; then
      echo "   $candidate is missing (a run trained without --keep-epochs?): skipped" >&2
      continue
    fi
    name="$(basename "${candidate%.pt}")"
    [[ "$candidate" == "$start" ]] && name="start"
    result="$(validation_steps "$candidate" "$run/validation/$name")"
    read -r steps successes episodes <<<"$result"
    echo "$candidate,$(relative "$validation"),$steps,$successes,$episodes" >>"$run/selection.csv"
    echo "   $name: $steps steps on the validation scenes, $successes / $episodes clear" >&2
    if [[ -z "$best" ]] || python3 -c "import sys; sys.exit(not $steps < $best_steps)"; then
      best="$candidate" best_steps="$steps"
    fi
  done
  cp "$best" "$run/chosen.pt"
  cp "${best%.pt}.json" "$run/chosen.json"
  echo "$best" >"$run/chosen.txt"  # which candidate (scripts/ship_model.sh records it)
  echo "   chosen: $best ($best_steps steps)" >&2
  echo "$run/chosen.pt"
}

dagger_data=()
for ((k = 1; k <= rounds; ++k)); do
  data_k="$out/data_$k"
  run_k="$out/model_$k"
  seed_k=$((first_seed + (k - 1) * stride))
  echo "== DAgger round $k: agent $model, scenes $scenes from seed $seed_k" >&2
  "$bin/occlusion_dagger" --model "$model" --out "$data_k" --scenes "$scenes" \
    --first-seed "$seed_k" --beta "$beta" --size "$size" --threads "$threads" \
    --source sweethome3d --category chair --category table
  dagger_data+=(--data "$data_k")
  # shellcheck disable=SC2046  # the flags are words
  "$bin/occlusion_train" --data "$base" "${extra[@]}" "${dagger_data[@]}" --out "$run_k" \
    --init-from "$model" --epochs "$epochs" --lr "$lr" --keep-epochs $(network_flags "$model")
  chosen="$(choose_model "$out" "$k" "$model")"
  model="$(relative "$chosen")"
done
echo "dagger.sh: round $rounds's model: $model" >&2
