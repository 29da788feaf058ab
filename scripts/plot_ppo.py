#!/usr/bin/env python3
"""The paper's Figure 3 for PPO runs: rolling reward and steps per episode over training.

Usage: plot_ppo.py RUN_DIR [RUN_DIR ...] [--out PNG] [--window N]
Reads each RUN_DIR/training_episodes.csv (occlusion_train_ppo). With one run and no --out the figure is
RUN_DIR/curves.png; several runs (e.g. union and intersection) share one figure, one line each.
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rolling(values, window):
    out, total = [], 0.0
    for i, value in enumerate(values):
        total += value
        if i >= window:
            total -= values[i - window]
        out.append(total / min(i + 1, window))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--out")
    parser.add_argument("--window", type=int, default=100, help="episodes in the rolling mean")
    args = parser.parse_args()
    figure, (reward_axis, steps_axis) = plt.subplots(1, 2, figsize=(11, 4))
    for run in args.runs:
        path = os.path.join(run, "training_episodes.csv")
        with open(path) as f:
            rows = list(csv.DictReader(f))
        if not rows:
            print(f"plot_ppo: {path} has no episodes yet", file=sys.stderr)
            continue
        env_steps = [int(r["env_steps"]) for r in rows]
        label = os.path.basename(os.path.normpath(run))
        reward_axis.plot(env_steps, rolling([float(r["reward"]) for r in rows], args.window),
                         label=label)
        steps_axis.plot(env_steps, rolling([float(r["steps"]) for r in rows], args.window),
                        label=label)
    reward_axis.set(xlabel="environment steps", ylabel=f"episode reward (mean of {args.window})",
                    title="Reward per episode")
    steps_axis.set(xlabel="environment steps", ylabel=f"steps per episode (mean of {args.window})",
                   title="Steps per episode (failures at the limit)")
    for axis in (reward_axis, steps_axis):
        axis.grid(alpha=0.3)
        axis.legend()
    figure.tight_layout()
    out = args.out or os.path.join(args.runs[0], "curves.png")
    figure.savefig(out, dpi=110)
    print(f"plot_ppo: wrote {out}")


if __name__ == "__main__":
    main()
