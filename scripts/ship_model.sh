#!/usr/bin/env bash
# Copies a training run's model into models/ under NAME and records it in models/MANIFEST.md:
# what it is, from which data, with which command, its metrics and its sha256. A network run
# (occlusion_train) ships best.pt, or chosen.pt where scripts/dagger.sh chose one by the agent's
# steps on validation scenes (with that choice: selection.csv, chosen.txt); a PPO run
# (occlusion_train_ppo) ships policy.pt with the end points of its training curves (the last 500
# episodes) and the sha256 of its backbone. A chosen.pt made by occlusion_train
# --half-precision-copy or --eight-bit-copy (float16 or 8-bit weights) records the sha256 of the
# float32 model it copies.
# Models derived without training (scripts/derive_model.py) keep their own table.
# Usage: scripts/ship_model.sh RUN_DIR NAME "THE TRAINING COMMAND"
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
run=${1:?usage: ship_model.sh RUN_DIR NAME COMMAND}
name=${2:?usage: ship_model.sh RUN_DIR NAME COMMAND}
command=${3:?usage: ship_model.sh RUN_DIR NAME COMMAND}
if [[ -f "$run/chosen.pt" && -f "$run/chosen.json" ]]; then
  model=chosen
elif [[ -f "$run/best.pt" && -f "$run/best.json" ]]; then
  model=best
elif [[ -f "$run/policy.pt" && -f "$run/policy.json" ]]; then
  model=policy
else
  echo "ship_model: neither best.pt/best.json nor policy.pt/policy.json in $run" >&2
  exit 1
fi
validation=""
if [[ "$model" == policy ]]; then
  # The policy's mean action on the 50 validation scenes (seeds 900000.., train-split models).
  agents="$root/.build_ws/devel/lib/occlusion_env/occlusion_agents"
  [[ -x "$agents" ]] || { echo "ship_model: $agents not built (make build)" >&2; exit 1; }
  validation=$("$agents" --agents policy --model "$run/policy.pt" --source sweethome3d \
      --category chair --category table --model-split train --first-seed 900000 --scenes 50 \
      2>/dev/null | grep '^policy ')
fi
mkdir -p "$root/models"
cp "$run/$model.pt" "$root/models/$name.pt"
python3 - "$run" "$model" "$root/models/$name.json" "$name" "$command" "$validation" "$root" <<'PY'
import csv, hashlib, json, os, sys
run, model, out, name, command, validation, root = sys.argv[1:]
manifest = json.load(open(os.path.join(run, model + ".json")))
manifest["file"] = name + ".pt"
manifest["command"] = command
if "dataset" in manifest:
    # The dataset the network was trained on, by the checksum of its manifest (dataset.json).
    # A relative dataset path is relative to the source tree, where the trainer ran.
    dataset_json = os.path.join(root, manifest["dataset"], "dataset.json")
    manifest["dataset_manifest_sha256"] = hashlib.sha256(open(dataset_json, "rb").read()).hexdigest()
for key in ("copy_of", "half_precision_of"):
    # A float16 or 8-bit copy (occlusion_train --half-precision-copy, --eight-bit-copy; the first
    # float16 copies said "half_precision_of"): the float32 model it was made from.
    if key in manifest and not key + "_sha256" in manifest:
        source = os.path.join(root, manifest[key])
        manifest[key + "_sha256"] = hashlib.sha256(open(source, "rb").read()).hexdigest()
        break
if model == "chosen":
    # The DAgger round's choice: every candidate's mean steps on the validation scenes.
    rows = list(csv.DictReader(open(os.path.join(run, "selection.csv"))))
    manifest["chosen_by"] = {
        # selection.csv's optional "selected_by" says how, where the choice was not dagger.sh's.
        "scenes": rows[0].get("scene_set", "config/scenes/validation_sweethome3d.yaml") + ", "
                  + (rows[0].get("selected_by")
                     or "predicted_escape, 50 steps at most (scripts/dagger.sh)"),
        "candidates": [{"model": r["candidate"], "mean_steps": float(r["mean_steps"]),
                        "successes": int(r["successes"]), "episodes": int(r["episodes"])}
                       for r in rows],
        "chosen": open(os.path.join(run, "chosen.txt")).read().strip(),
    }
if manifest.get("kind") == "ppo_policy":
    episodes = list(csv.DictReader(open(os.path.join(run, "training_episodes.csv"))))[-500:]
    manifest["training_end"] = {
        "episodes": len(episodes),
        "mean_steps": sum(float(e["steps"]) for e in episodes) / len(episodes),
        "mean_reward": sum(float(e["reward"]) for e in episodes) / len(episodes),
        "success_rate": sum(int(e["success"]) for e in episodes) / len(episodes),
    }
    backbone = manifest["trained_with"]["backbone_path"]
    manifest["backbone_sha256"] = hashlib.sha256(open(backbone, "rb").read()).hexdigest()
    manifest["backbone"] = os.path.basename(backbone)
    # "policy   10.3 +/-   3.8      0/50    100.0 %"
    fields = validation.replace("+/-", " ").replace("/", " ").replace("%", " ").split()
    manifest["validation"] = {
        "scenes": "sweethome3d chair,table, train split, seeds 900000..900049, start azimuth 0, "
                  "256 px, 50 steps at most (occlusion_agents)",
        "mean_steps": float(fields[1]), "std_steps": float(fields[2]),
        "failures": int(fields[3]), "episodes": int(fields[4]), "success_rate": float(fields[5]) / 100,
    }
json.dump(manifest, open(out, "w"), indent=2)
PY
python3 - "$root/models" <<'PY'
import glob, hashlib, json, os, sys
models = sys.argv[1]
lines = ["# Shipped models", "",
         "Generated by `scripts/ship_model.sh`; each model is `<name>.pt` with its manifest "
         "`<name>.json` (network, training options, dataset options, validation metrics, command).", ""]
lines += ["| model | network | dataset | epoch | val IoU | gradient / escape angle | size | sha256 |",
          "| --- | --- | --- | ---: | ---: | --- | ---: | --- |"]
policies, derived, chosen_notes = [], [], []


def frames_per_scene(ds):
    # A DAgger dataset (occlusion_dagger) holds the states of the agent's own roll-outs.
    if "dagger" in ds:
        return f"roll-outs of {os.path.basename(ds['dagger']['model'])}"
    return f"{ds['frames']} frames/scene"


for path in sorted(glob.glob(os.path.join(models, "*.json"))):
    m = json.load(open(path))
    if m.get("kind") == "ppo_policy":
        policies.append(m)
        continue
    if "derived_from" in m:
        derived.append(m)
        continue
    if "network" not in m:
        continue
    pt = os.path.join(models, m["file"])
    digest = hashlib.sha256(open(pt, "rb").read()).hexdigest()
    net = m["network"]
    v = m["validation"]
    loss = m["training"]["direction_loss"]
    ds = m["dataset_options"]
    lines.append(f"| `{m['file']}` | {net['variant']}{'-L1' if loss == 'smooth_l1' else ''}, "
                 f"{net['input_size']} px, base {net['base_channels']}"
                 f"{', float16 weights' if m.get('weights') == 'float16' else ''} | {ds['source']} "
                 f"{','.join(ds['categories']) or 'any'}, seeds {ds['first_seed']}.., "
                 f"{frames_per_scene(ds)}, {ds['size']} px"
                 f"{', dataset.json sha256 ' + m['dataset_manifest_sha256'][:12] + '...' if 'dataset_manifest_sha256' in m else ''}"
                 f"{' + ' + ', '.join(m['extra_datasets']) if m.get('extra_datasets') else ''}"
                 f" | {m['epoch']} | "
                 f"{100 * v['val_iou']:.2f} % | {v['val_gradient_angle_deg']:.1f} / "
                 f"{v['val_escape_angle_deg']:.1f} deg | {os.path.getsize(pt) / 1e6:.1f} MB | "
                 f"`{digest}` |")
    if "chosen_by" in m:
        c = m["chosen_by"]
        steps = ", ".join(f"{x['model']} {x['mean_steps']:.2f}" for x in c["candidates"])
        chosen_notes.append(f"`{m['file']}` was chosen by the agent's mean steps on {c['scenes']} "
                            f"among: {steps}.")
if chosen_notes:
    lines += [""] + chosen_notes
if derived:
    lines += ["", "Derived without training (`scripts/derive_model.py`: the weights copied, network "
              "fields of the manifest changed):", "",
              "| model | from | changed | size | sha256 |", "| --- | --- | --- | ---: | --- |"]
    for m in derived:
        d = m["derived_from"]
        pt = os.path.join(models, m["file"])
        digest = hashlib.sha256(open(pt, "rb").read()).hexdigest()
        changed = ", ".join(f"`{k}: {v}`" for k, v in d["changed"].items())
        lines.append(f"| `{m['file']}` | `{d['file']}` (sha256 {d['sha256'][:12]}...) | {changed} | "
                     f"{os.path.getsize(pt) / 1e6:.1f} MB | `{digest}` |")
    lines += ["", "(The derived files hold the same bytes as their source: git stores them once. Their "
              "manifests differ.)"]
    lines += ["", "Their figures and what they are for: doc/TRAINING.md, \"Training for real cameras\" (the",
              "`_fov60` models: \"A fixed angle of view\")."]
if policies:
    lines += ["", "PPO policies (`occlusion_train_ppo`); the training curves' end points are the means "
              "of the last episodes of training (sampled actions, random start azimuths):", "",
              "| policy | reward | recipe | backbone | env steps | training end: steps / reward / "
              "success | validation: steps, success | size | sha256 |",
              "| --- | --- | --- | --- | ---: | --- | --- | ---: | --- |"]
    for m in policies:
        t = m["trained_with"]
        recipe = ("actor from the escape head" if t["actor_from_escape"] else "actor from scratch") + \
                 (", rig inputs" if t["policy"]["rig_inputs"] else ", image only") + \
                 f", lambda {t['gae_lambda']}, minibatch {t['minibatch_size']}, target KL {t['target_kl']}"
        end = m["training_end"]
        pt = os.path.join(models, m["file"])
        digest = hashlib.sha256(open(pt, "rb").read()).hexdigest()
        lines.append(f"| `{m['file']}` | {t['reward']} | {recipe} | `{m['backbone']}` "
                     f"(sha256 {m['backbone_sha256'][:12]}...) | {m['env_steps']} | "
                     f"{end['mean_steps']:.1f} / {end['mean_reward']:.2f} / "
                     f"{100 * end['success_rate']:.0f} % (last {end['episodes']}) | "
                     f"{m['validation']['mean_steps']:.1f} +/- {m['validation']['std_steps']:.1f}, "
                     f"{100 * m['validation']['success_rate']:.0f} % | "
                     f"{os.path.getsize(pt) / 1e6:.1f} MB | `{digest}` |")
lines += ["", "Commands:", ""]
for path in sorted(glob.glob(os.path.join(models, "*.json"))):
    m = json.load(open(path))
    if "command" in m:
        lines.append(f"- `{m['file']}`: `{m['command']}`")
lines += ["", "Policies' validation: the mean action on 50 validation scenes (Sweet Home 3D chairs and "
          "tables of the train split, seeds 900000-900049, start azimuth 0, 50 steps at most), "
          "run by `occlusion_agents --agents policy --model <file> --source sweethome3d --category "
          "chair --category table --model-split train --first-seed 900000 --scenes 50`.", ""]
lines += ["", "The dataset is regenerated with the `occlusion_dataset` command in doc/TRAINING.md "
          "(\"Training data\")."]
open(os.path.join(models, "MANIFEST.md"), "w").write("\n".join(lines) + "\n")
PY
echo "ship_model: models/$name.pt and models/MANIFEST.md written"
