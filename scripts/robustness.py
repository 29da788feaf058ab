#!/usr/bin/env python3
"""The robustness table (EVALUATION.md, "Robustness"): models under each camera condition.

For every condition (void or room, each depth sensor, and the randomised camera) and every model:
  - occlusion IoU and escape-direction error on held-out frames: a check dataset per condition
    (occlusion_dataset, seeds 960000.., train-split models, oracle labels; scenes neither model
    was trained or chosen on), scored by `occlusion_train --check`;
  - the predicted-escape agent's mean steps and success on the held-out scene sets
    (`occlusion_eval --scenes ... --world/--depth-sensor/--randomize`): test seeds, so test worlds.
Every step's output is kept under --out and reused when the script runs again (delete a file to
redo it). --conditions picks some of the conditions, --no-agents leaves the agents' episodes out
(IoU and escape error only, minutes instead of half an hour), --mask-coverage scores the IoU
against labels at another coverage than the paper's half a network pixel. Prints the Markdown table and writes OUT/robustness.md, OUT/robustness.json and
OUT/robustness.png.

Usage: scripts/robustness.py --model clean=models/multitask_unet64.pt \
           --model robust=models/multitask_robust64.pt --out /tmp/robustness
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, ".build_ws", "devel", "lib", "occlusion_env")

# name -> the flags of occlusion_dataset and occlusion_eval that make it
CONDITIONS = [
    ("void, ideal", ["--world", "void", "--depth-sensor", "ideal"]),
    ("room, ideal", ["--world", "room", "--depth-sensor", "ideal"]),
    ("void, kinect_v1", ["--world", "void", "--depth-sensor", "kinect_v1"]),
    ("void, realsense_d435", ["--world", "void", "--depth-sensor", "realsense_d435"]),
    ("void, azure_kinect", ["--world", "void", "--depth-sensor", "azure_kinect"]),
    ("room, kinect_v1", ["--world", "room", "--depth-sensor", "kinect_v1"]),
    ("room, realsense_d435", ["--world", "room", "--depth-sensor", "realsense_d435"]),
    ("room, azure_kinect", ["--world", "room", "--depth-sensor", "azure_kinect"]),
    ("randomised", ["--randomize"]),
]
SCENE_SETS = ["test_sweethome3d", "test_sweethome3d_unseen"]


def slug(condition):
    return condition.replace(", ", "_")


def run(command, log_path):
    print("robustness:", " ".join(command), file=sys.stderr, flush=True)
    with open(log_path, "w") as log:
        status = subprocess.call(command, stdout=log, stderr=subprocess.STDOUT, cwd=ROOT)
    if status != 0:
        sys.exit("robustness: failed (%d), see %s" % (status, log_path))


def check_data(args, condition, flags):
    out = os.path.join(args.out, "data", slug(condition))
    os.makedirs(os.path.dirname(out), exist_ok=True)
    if not os.path.exists(os.path.join(out, "dataset.json")) or os.path.exists(out + ".partial"):
        open(out + ".partial", "w").close()
        run([os.path.join(BIN, "occlusion_dataset"), "--out", out, "--scenes", str(args.scenes),
             "--frames", str(args.frames), "--first-seed", str(args.first_seed), "--source",
             "sweethome3d", "--category", "chair", "--category", "table", "--validation", "0",
             "--threads", str(args.threads)] + flags, out + ".log")
        os.remove(out + ".partial")
    return out


def check_model(args, model_name, model_path, condition, data):
    coverage = "" if args.mask_coverage == 0.5 else "_coverage%g" % args.mask_coverage
    out = os.path.join(args.out, "check", "%s_%s%s.json" % (model_name, slug(condition), coverage))
    os.makedirs(os.path.dirname(out), exist_ok=True)
    if not os.path.exists(out):
        run([os.path.join(BIN, "occlusion_train"), "--check", model_path, "--data", data, "--out",
             out, "--threads", str(args.threads), "--mask-coverage", str(args.mask_coverage)],
            out + ".log")
    with open(out) as f:
        check = json.load(f)
    return {"iou": check["figures"]["val_iou"],
            "escape_deg": check["figures"]["val_escape_angle_deg"], "frames": check["frames"]}


def agent_episodes(args, model_name, model_path, condition, flags, scene_set):
    out = os.path.join(args.out, "agents", "%s_%s" % (model_name, slug(condition)))
    episodes = os.path.join(out, scene_set + "_episodes.csv")
    if not os.path.exists(os.path.join(out, scene_set + "_summary.md")):
        os.makedirs(out, exist_ok=True)
        run([os.path.join(BIN, "occlusion_eval"), "--scenes",
             os.path.join(ROOT, "config", "scenes", scene_set + ".yaml"), "--agents",
             "predicted_escape", "--model", model_path, "--out", out, "--no-plots"] + flags,
            os.path.join(out, scene_set + ".log"))
    with open(episodes) as f:
        rows = [row for row in csv.DictReader(f) if row["agent"] == "predicted_escape"]
    steps = [int(row["steps"]) for row in rows]  # a failure counts at the step limit
    return {"mean_steps": statistics.mean(steps),
            "success": sum(int(row["success"]) for row in rows) / len(rows),
            "scenes": len(rows)}


def markdown(results, models, scene_sets=SCENE_SETS):
    names = [name for name, _ in models]
    head = ["condition"]
    head += ["IoU %s" % n for n in names] + ["escape error %s" % n for n in names]
    for scene_set in scene_sets:
        head += ["%s: steps (success) %s" % (scene_set, n) for n in names]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" + "---:|" * (len(head) - 1)]
    for condition, _ in CONDITIONS:
        if condition not in results:
            continue
        r = results[condition]
        cells = [condition]
        cells += ["%.1f %%" % (100 * r[n]["check"]["iou"]) for n in names]
        # null: frames without escape labels (made with --no-oracle)
        cells += ["-" if r[n]["check"]["escape_deg"] is None else
                  "%.1f deg" % r[n]["check"]["escape_deg"] for n in names]
        for scene_set in scene_sets:
            for n in names:
                a = r[n][scene_set]
                cells.append("%.1f (%d %%)" % (a["mean_steps"], round(100 * a["success"])))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def plot(results, models, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("robustness: no matplotlib, no plot", file=sys.stderr)
        return
    names = [name for name, _ in models]
    labels = [c for c, _ in CONDITIONS if c in results]
    panels = [("occlusion IoU [%]", lambda r, n: 100 * r[n]["check"]["iou"]),
              ("escape-direction error [deg]",
               lambda r, n: float("nan") if r[n]["check"]["escape_deg"] is None
               else r[n]["check"]["escape_deg"])]
    if "test_sweethome3d" in results[labels[0]][names[0]]:
        panels.append(("predicted_escape mean steps, test_sweethome3d",
                       lambda r, n: r[n]["test_sweethome3d"]["mean_steps"]))
    fig, axes = plt.subplots(1, len(panels), figsize=(5.4 * len(panels), 4.8))
    width = 0.8 / len(names)
    for ax, (title, value) in zip(axes, panels):
        for k, n in enumerate(names):
            xs = [i + (k - (len(names) - 1) / 2) * width for i in range(len(labels))]
            ax.bar(xs, [value(results[c], n) for c in labels], width, label=n)
        ax.set_xticks(range(len(labels)))
        ax.set_xticklabels(labels, rotation=45, ha="right", fontsize=8)
        ax.set_title(title, fontsize=10)
        ax.grid(axis="y", alpha=0.3)
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def agent_network(summary):
    """The agent's network of a bridge summary; before --agent-model the agent ran the bridge's."""
    if "agent_model" in summary:
        return summary["agent_model"]
    if summary["model"] == "shipped default":
        return "models/multitask_unet64_camera.pt"
    return summary["model"]


def networks(summary):
    """The model column: one network, or the agent's and the bridge's when they differ (the
    launch files' defaults by name)."""
    bridge = summary["model"]
    if bridge == "shipped default":
        bridge = "models/multitask_unet64_camera.pt"
    agent = agent_network(summary)
    if agent == "shipped default":
        agent = "models/multitask_unet64_camera_agent.pt"
    if agent == bridge:
        return agent
    return "agent %s, bridge %s" % (agent, bridge)


def bridge_rows(paths):
    """Rows of scripts/bridge_evaluation.py summaries (OUT/bridge_summary.json)."""
    lines = ["| model | scenes | stand-in world, sensor | truly clear at the end | the bridge's "
             "verdict agrees | mean steps | oracle's mean steps | ratio |",
             "|---|---|---|---:|---:|---:|---:|---:|"]
    for path in paths:
        with open(os.path.join(path, "bridge_summary.json")) as f:
            b = json.load(f)
        n = b["episodes"]
        lines.append("| %s | %s | %s, %s | %d / %d (%.0f %%) | %d / %d (%.0f %%) | %.2f | %.2f | %.2f |"
                     % (networks(b), os.path.basename(b["scenes"]), b["world"],
                        b["depth_sensor"], b["truly_clear"], n, 100.0 * b["truly_clear"] / n,
                        b["verdict_agrees"], n, 100.0 * b["verdict_agrees"] / n, b["mean_steps"],
                        b["oracle_mean_steps"], b["steps_over_oracle"]))
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--model", action="append", required=True,
                        help="NAME=PATH of a multi-task network model; repeat for each")
    parser.add_argument("--out", required=True, help="where data, figures and the table go")
    parser.add_argument("--scenes", type=int, default=30, help="check scenes per condition")
    parser.add_argument("--frames", type=int, default=10, help="frames per check scene")
    parser.add_argument("--first-seed", type=int, default=960000,
                        help="first seed of the check scenes (below 1,000,000; not trained on)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--conditions", default="",
                        help="only these conditions, by name, separated by ';' (e.g. 'void, "
                             "ideal;randomised'); default all")
    parser.add_argument("--no-agents", action="store_true",
                        help="no agent episodes: IoU and escape error only")
    parser.add_argument("--mask-coverage", type=float, default=0.5,
                        help="a network pixel's label is occluded where at least this fraction "
                             "of it is (the paper's 0.5; occlusion_train --mask-coverage)")
    parser.add_argument("--bridge", action="append", default=[],
                        help="a scripts/bridge_evaluation.py --out folder whose summary joins the "
                             "report; repeatable")
    parser.add_argument("--section", default="",
                        help="also write the report as a Markdown section to this file (for "
                             "scripts/evaluate.sh, which appends doc/robustness/*.md.in; links relative to the "
                             "repository's root, as in EVALUATION.md)")
    args = parser.parse_args()
    models = [tuple(m.split("=", 1)) for m in args.model]
    if any(len(m) != 2 for m in models):
        sys.exit("robustness: --model takes NAME=PATH")
    for _, path in models:
        if not os.path.exists(path):
            sys.exit("robustness: no model at %s" % path)
    condition_names = [c for c, _ in CONDITIONS]
    chosen = [c.strip() for c in args.conditions.split(";") if c.strip()] or condition_names
    unknown = [c for c in chosen if c not in condition_names]
    if unknown:
        sys.exit("robustness: no condition %s (the conditions: %s)"
                 % (", ".join(unknown), "; ".join(condition_names)))
    if not 0.0 < args.mask_coverage <= 1.0:
        sys.exit("robustness: --mask-coverage must lie in (0, 1]")
    scene_sets = [] if args.no_agents else SCENE_SETS
    results = {}
    for condition, flags in CONDITIONS:
        if condition not in chosen:
            continue
        data = check_data(args, condition, flags)
        results[condition] = {}
        for name, path in models:
            r = {"check": check_model(args, name, path, condition, data)}
            for scene_set in scene_sets:
                r[scene_set] = agent_episodes(args, name, path, condition, flags, scene_set)
            results[condition][name] = r
    table = markdown(results, models, scene_sets)
    if args.bridge:
        table += "\nThrough the camera bridge (scripts/bridge_evaluation.py):\n\n" + bridge_rows(args.bridge)
    print(table)
    with open(os.path.join(args.out, "robustness.md"), "w") as f:
        f.write(table)
    with open(os.path.join(args.out, "robustness.json"), "w") as f:
        json.dump({"models": dict(models), "results": results}, f, indent=1)
    plot(results, models, os.path.join(args.out, "robustness.png"))
    if args.section:
        write_section(args, models, table)


def bridge_commands(paths):
    """The scripts/bridge_evaluation.py command behind each bridge summary."""
    commands = []
    for path in paths:
        with open(os.path.join(path, "bridge_summary.json")) as f:
            b = json.load(f)
        # Summaries before 2026-11-26 said "shipped default"; later ones name the default and
        # say that it was one.
        default = b["model"] == "shipped default" or b.get("model_is_default", False)
        model = "" if default else " --model " + b["model"]
        agent = agent_network(b)
        if agent != "shipped default" and not b.get("agent_model_is_default", False):
            model += " --agent-model " + agent
        if b.get("occlusion_probability") is not None:
            model += " --occlusion-probability %r" % b["occlusion_probability"]
        commands.append("scripts/bridge_evaluation.py --world %s --depth-sensor %s%s --out %s"
                        % (b["world"], b["depth_sensor"], model, os.path.relpath(path, ROOT)))
    return commands


def write_section(args, models, table):
    """The report as EVALUATION.md's section: what was measured, how, and the table and plot."""
    folder = os.path.dirname(os.path.abspath(args.section))
    image = os.path.join(folder, os.path.basename(args.section).split(".")[0] + ".png")
    os.replace(os.path.join(args.out, "robustness.png"), image)
    command = ["scripts/robustness.py"] + ["--model %s=%s" % m for m in models]
    command += ["--bridge %s" % b for b in args.bridge] + ["--out OUT", "--section " + args.section]
    if args.mask_coverage != 0.5:
        command.append("--mask-coverage %g" % args.mask_coverage)
    if args.conditions:
        command.append("--conditions '%s'" % args.conditions)
    if args.no_agents:
        command.append("--no-agents")
    text = [
        "## Robustness: the camera conditions (issue 27)", "",
        "Each model under each condition (doc/SENSORS.md): occlusion IoU and escape-direction error "
        "on %d held-out frames per condition (%d scenes x %d frames, seeds %d.., train-split models "
        "that no model was trained or chosen on; `occlusion_train --check`), and the "
        "predicted-escape agent's mean steps (failures at 50) and success on the held-out scene "
        "sets, whose test seeds draw the room, the sensor's noise and, randomised, the camera "
        "(`occlusion_eval --scenes ... --world W --depth-sensor S` or `--randomize`). A network "
        "pixel is labelled occluded where at least %g of its area is. Regenerate "
        "with:" % (args.scenes * args.frames, args.scenes, args.frames, args.first_seed,
                   args.mask_coverage), "",
        "```", " ".join(command)] + bridge_commands(args.bridge) + ["```", "",
        "The models: " + ", ".join("`%s` (`%s`)" % m for m in models) + "; how each was made: "
        "[doc/TRAINING.md](doc/TRAINING.md#training-for-real-cameras). The bridge rows run the "
        "stand-in camera, the bridge and the agent node over ROS and read the stand-in's truth "
        "where each episode ended ([doc/CAMERA_BRIDGE.md](doc/CAMERA_BRIDGE.md)); the oracle's "
        "steps are its episodes on the same scenes in `doc/evaluation/test_sweethome3d_episodes.csv` "
        "(in the void: it reads the scene, not the camera).", "",
        table,
        "![robustness](%s)" % os.path.relpath(image, ROOT), ""]
    with open(args.section, "w") as f:
        f.write("\n".join(text))


if __name__ == "__main__":
    main()
