#!/usr/bin/env python3
"""Step rates from Python against C++ on the same scenes and actions (BENCHMARKS.md, "From
Python"): the in-process env, the C++ loop (occlusion_step_rate), the vector env's aggregate rate
and, with --ros-namespace, the ROS-backed env. Repetitions alternate between the in-process
Python and C++ runs, so a slow minute of a shared machine hits both; medians are printed.

    source .build_ws/devel/setup.bash
    python3 bench/python_step_rate.py --size 256 --repetitions 5
    bash bench/python_step_rate_ros.sh          # the same with a simulator node, over ROS
"""

import argparse
import json
import math
import os
import statistics
import subprocess
import time

import numpy as np

import occlusion_env


def actions(steps):
    """Action t = (cos(0.3 t), sin(0.3 t)), as occlusion_step_rate steps."""
    t = np.arange(steps)
    return np.stack([np.cos(0.3 * t), np.sin(0.3 * t)], axis=1)


def single_env_rate(env, first_seed, episodes, steps):
    moves = actions(steps)
    total, stepping = 0, 0.0
    for episode in range(episodes):
        env.reset(seed=first_seed + episode)
        start = time.perf_counter()
        for t in range(steps):
            _, _, terminated, truncated, _ = env.step(moves[t])
            total += 1
            if terminated or truncated:
                break
        stepping += time.perf_counter() - start
    return total / stepping, total


def cpp_rate(binary, options, first_seed, episodes, steps):
    output = subprocess.run([binary, json.dumps(options), str(first_seed), str(episodes),
                             str(steps)], check=True, capture_output=True, text=True).stdout
    fields = output.split()
    return float(fields[fields.index("steps_per_second") + 1]), int(fields[1])


def vector_rate(num_envs, options, steps):
    envs = occlusion_env.make_vector(num_envs, **options)
    envs.reset(seed=1)
    envs.action_space.seed(1)
    start = time.perf_counter()
    for _ in range(steps):
        envs.step(envs.action_space.sample())
    rate = num_envs * steps / (time.perf_counter() - start)
    envs.close()
    return rate


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--episodes", type=int, default=5, help="scenes (seeds 1..episodes)")
    parser.add_argument("--steps", type=int, default=100, help="steps per scene at most")
    parser.add_argument("--repetitions", type=int, default=5)
    parser.add_argument("--vector-envs", default="2,4", help="vector sizes to measure")
    parser.add_argument("--ros-namespace", default="", help="also the ROS-backed env there")
    parser.add_argument("--binary", default=os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", ".build_ws", "devel", "lib",
        "occlusion_env", "occlusion_step_rate"))
    args = parser.parse_args()
    options = {"width": args.size, "height": args.size, "max_steps": args.steps}
    env = occlusion_env.make(**options)
    rows = {"C++ loop (occlusion_step_rate)": [], "Python, in process": []}
    for _ in range(args.repetitions):
        cpp, cpp_steps = cpp_rate(args.binary, options, 1, args.episodes, args.steps)
        python, python_steps = single_env_rate(env, 1, args.episodes, args.steps)
        assert cpp_steps == python_steps, "the same scenes and actions take the same steps"
        rows["C++ loop (occlusion_step_rate)"].append(cpp)
        rows["Python, in process"].append(python)
    env.close()
    ratios = [p / c for p, c in zip(rows["Python, in process"], rows["C++ loop (occlusion_step_rate)"])]
    for count in [int(n) for n in args.vector_envs.split(",") if n]:
        rows[f"Python vector env, {count} envs (aggregate)"] = [
            vector_rate(count, options, 200) for _ in range(args.repetitions)]
    if args.ros_namespace:
        ros_env = occlusion_env.make_ros(args.ros_namespace)
        rows["Python over ROS (RosOcclusionEnv)"] = [
            single_env_rate(ros_env, 1, args.episodes, args.steps)[0]
            for _ in range(args.repetitions)]
        ros_env.close()
    print(f"{args.size} x {args.size} px, embedded objects, {args.episodes} scenes x <= "
          f"{args.steps} steps, {args.repetitions} repetitions; steps/s (ms/step), medians")
    for name, rates in rows.items():
        median = statistics.median(rates)
        print(f"| {name} | {median:.0f} ({1000 / median:.3f} ms) | "
              f"{min(rates):.0f}-{max(rates):.0f} |")
    print(f"Python / C++ in process: median {statistics.median(ratios):.3f} "
          f"(per repetition {', '.join(f'{r:.3f}' for r in ratios)})")
    if math.isfinite(statistics.median(ratios)) and statistics.median(ratios) < 0.9:
        print("below the 90 % target")


if __name__ == "__main__":
    main()
