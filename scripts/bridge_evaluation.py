#!/usr/bin/env python3
"""The camera path scored end to end (doc/CAMERA_BRIDGE.md, "On held-out scenes, end to end").

Starts launch/bridge_evaluation.launch: the stand-in camera (the simulator publishing only what a
camera and a robot give, in the chosen world and with the chosen depth sensor), the camera bridge
with a network model, and the predicted_escape agent node on every seed of a scene set. Listens to
the stand-in's truth (occlusion/ground_truth/view) and scores each episode where it really ended:
  - truly clear: the stand-in's own occlusion at the last view is below its threshold;
  - the bridge's verdict (the episode's success) agrees with that truth;
  - mean steps (failures at the step limit) against the oracle's on the same scenes, read from an
    occlusion_eval episode CSV (the oracle reads the scene, not the camera, so its steps do not
    depend on the sensor; in a room they depend on the world, where the camera stays above the
    floor: give --oracle-csv the oracle's episodes in the same world, e.g. occlusion_eval --scenes
    config/scenes/test_sweethome3d.yaml --agents oracle --world room --out OUT).
Writes OUT/bridge_episodes.csv (the agent's), OUT/bridge_truth.csv, OUT/bridge_summary.json and
prints a summary. Run it in a sourced workspace (source .build_ws/devel/setup.bash) with
/usr/bin/python3; it starts its own ROS master (roslaunch) when none runs.

  scripts/bridge_evaluation.py --world room --depth-sensor realsense_d435 --out /tmp/bridge_d435
"""
import argparse
import csv
import json
import os
import signal
import statistics
import subprocess
import sys
import threading
import time

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read_rows(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def oracle_steps(path, seeds):
    rows = {int(r["scene_seed"]): int(r["steps"]) for r in read_rows(path) if r["agent"] == "oracle"}
    missing = [s for s in seeds if s not in rows]
    if missing:
        sys.exit("bridge_evaluation: no oracle episode for seeds %s in %s" % (missing[:5], path))
    return [rows[s] for s in seeds]


# The networks bridge_evaluation.launch uses when none is given (its `model` and `agent_model`
# defaults; test_scripts.py checks that the launch file names them).
DEFAULT_MODEL = "models/multitask_unet128_bridge_fov60.pt"
DEFAULT_AGENT_MODEL = "models/multitask_unet64_robust.pt"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scenes", default=os.path.join(ROOT, "config/scenes/test_sweethome3d.yaml"))
    parser.add_argument("--limit", type=int, default=0, help="only the first N scenes (0: all)")
    parser.add_argument("--world", default="void", help="void | room | random")
    parser.add_argument("--depth-sensor", default="ideal",
                        help="ideal | kinect_v1 | realsense_d435 | azure_kinect | random")
    parser.add_argument("--model", default="",
                        help="the bridge's network, whose estimate ends an episode ('': the "
                        "shipped default)")
    parser.add_argument("--occlusion-probability", type=float, default=None,
                        help="the bridge's ~occlusion_probability (default: config/camera_bridge.yaml's, "
                        "chosen for the default model)")
    parser.add_argument("--occlusion-threshold", type=int, default=None,
                        help="the bridge's ~occlusion_threshold [px] (default: config/camera_bridge.yaml's)")
    parser.add_argument("--confirm-views", type=int, default=None,
                        help="the bridge's ~confirm_views (default: config/camera_bridge.yaml's)")
    parser.add_argument("--second-model", default="",
                        help="the bridge's ~second_model: a second network whose estimate joins "
                        "--model's, a view clear only where both see none ('': none)")
    parser.add_argument("--second-occlusion-probability", type=float, default=None,
                        help="the bridge's ~second_occlusion_probability (default: "
                        "config/camera_bridge.yaml's)")
    parser.add_argument("--agent-model", default="",
                        help="the agent's network ('': the shipped default for an agent behind a "
                        "camera)")
    parser.add_argument("--oracle-csv",
                        default=os.path.join(ROOT, "doc/evaluation/test_sweethome3d_episodes.csv"),
                        help="occlusion_eval episodes with the oracle's rows on the same seeds, in "
                        "the same world (default: the void's, from doc/evaluation/)")
    parser.add_argument("--out", required=True)
    parser.add_argument("--timeout", type=float, default=60.0, help="[s] per episode at most")
    args = parser.parse_args()

    with open(args.scenes) as f:
        scene_set = yaml.safe_load(f)
    seeds = [int(s) for s in scene_set["seeds"]]
    if args.limit:
        seeds = seeds[:args.limit]
    oracle = oracle_steps(args.oracle_csv, seeds)
    os.makedirs(args.out, exist_ok=True)
    episodes_csv = os.path.abspath(os.path.join(args.out, "bridge_episodes.csv"))
    if os.path.exists(episodes_csv):
        os.remove(episodes_csv)

    try:
        import rospy
        from occlusion_env.msg import GroundTruthView
    except ImportError as error:
        sys.exit("bridge_evaluation: %s: source the workspace first "
                 "(source .build_ws/devel/setup.bash after make build)" % error)

    # This process's node name: the launch file starts the agent once it listens to the truth.
    scorer = "bridge_evaluation_%d" % os.getpid()
    command = ["roslaunch", "occlusion_env", "bridge_evaluation.launch",
               "seeds:=[%s]" % ", ".join(str(s) for s in seeds), "csv:=" + episodes_csv,
               "world:=" + args.world, "depth_sensor:=" + args.depth_sensor,
               "categories:=[%s]" % ", ".join(scene_set.get("categories", [])),
               "object_source:=" + scene_set.get("source", "sweethome3d"),
               "start_azimuth:=%r" % float(scene_set.get("start_azimuth", 0.0)),
               "scorer:=" + scorer]
    if args.model:
        command.append("model:=" + os.path.abspath(args.model))
    if args.agent_model:
        command.append("agent_model:=" + os.path.abspath(args.agent_model))
    if args.occlusion_probability is not None:
        command.append("occlusion_probability:=%r" % args.occlusion_probability)
    if args.second_model:
        command.append("second_model:=" + os.path.abspath(args.second_model))
    if args.second_occlusion_probability is not None:
        command.append("second_occlusion_probability:=%r" % args.second_occlusion_probability)
    if args.occlusion_threshold is not None:
        command.append("occlusion_threshold:=%d" % args.occlusion_threshold)
    if args.confirm_views is not None:
        command.append("confirm_views:=%d" % args.confirm_views)
    log = open(os.path.join(args.out, "roslaunch.log"), "w")
    print("bridge_evaluation:", " ".join(command), file=sys.stderr, flush=True)
    launch = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        last_view = {}
        lock = threading.Lock()

        def on_view(view):
            with lock:
                last_view[view.scene_seed] = view

        for _ in range(300):  # the master roslaunch starts
            try:
                rospy.init_node(scorer, disable_signals=True)
                break
            except Exception:
                time.sleep(0.1)
        rospy.Subscriber("/occlusion/ground_truth/view", GroundTruthView, on_view, queue_size=1000)
        deadline = time.time() + 30.0 + args.timeout * len(seeds)
        done = 0
        while done < len(seeds):
            if launch.poll() is not None:
                sys.exit("bridge_evaluation: roslaunch ended (%d); see %s/roslaunch.log"
                         % (launch.returncode, args.out))
            if time.time() > deadline:
                sys.exit("bridge_evaluation: timed out after %d of %d episodes" % (done, len(seeds)))
            rows = read_rows(episodes_csv)
            if len(rows) != done:
                done = len(rows)
                print("bridge_evaluation: %d / %d episodes" % (done, len(seeds)), file=sys.stderr,
                      flush=True)
            time.sleep(0.5)
        time.sleep(1.0)  # the last truth message
    finally:
        os.killpg(launch.pid, signal.SIGINT)
        try:
            launch.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(launch.pid, signal.SIGKILL)

    rows = {int(r["scene_seed"]): r for r in read_rows(episodes_csv)}
    truth_rows, clear, agree = [], 0, 0
    steps = []
    for seed in seeds:
        row = rows[seed]
        view = last_view.get(seed)
        if view is None:
            sys.exit("bridge_evaluation: no truth seen for seed %d" % seed)
        truly_clear = bool(view.unoccluded)
        said_clear = row["success"] == "1"
        clear += truly_clear
        agree += truly_clear == said_clear
        steps.append(int(row["steps"]))
        truth_rows.append({"scene_seed": seed, "bridge_steps": row["steps"],
                           "bridge_says_clear": int(said_clear), "truly_clear": int(truly_clear),
                           "truth_occlusion_px": view.occlusion.total_pixels,
                           "azimuth_rad": view.azimuth, "elevation_rad": view.elevation})
    with open(os.path.join(args.out, "bridge_truth.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(truth_rows[0].keys()))
        writer.writeheader()
        writer.writerows(truth_rows)
    summary = {"scenes": args.scenes, "episodes": len(seeds), "world": args.world,
               "depth_sensor": args.depth_sensor,
               "model": os.path.relpath(os.path.abspath(args.model), ROOT) if args.model
               else DEFAULT_MODEL,
               "model_is_default": not args.model,
               "agent_model": os.path.relpath(os.path.abspath(args.agent_model), ROOT)
               if args.agent_model else DEFAULT_AGENT_MODEL,
               "agent_model_is_default": not args.agent_model,
               "occlusion_probability": args.occlusion_probability,  # None: the config's
               "occlusion_threshold": args.occlusion_threshold,
               "confirm_views": args.confirm_views,
               "second_model": os.path.relpath(os.path.abspath(args.second_model), ROOT)
               if args.second_model else None,
               "second_occlusion_probability": args.second_occlusion_probability,
               "truly_clear": clear, "verdict_agrees": agree,
               "mean_steps": statistics.mean(steps), "oracle_mean_steps": statistics.mean(oracle),
               "steps_over_oracle": statistics.mean(steps) / statistics.mean(oracle)}
    with open(os.path.join(args.out, "bridge_summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    print("%s, %s, %s: truly clear at the end %d / %d (%.0f %%); the bridge's verdict agrees %d / %d "
          "(%.0f %%); mean steps %.2f, oracle %.2f, ratio %.2f"
          % (os.path.basename(args.scenes), args.world, args.depth_sensor, clear, len(seeds),
             100.0 * clear / len(seeds), agree, len(seeds), 100.0 * agree / len(seeds),
             summary["mean_steps"], summary["oracle_mean_steps"], summary["steps_over_oracle"]))


if __name__ == "__main__":
    main()
