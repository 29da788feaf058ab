#!/usr/bin/env python3
"""PPO training throughput of finished runs (BENCHMARKS.md, "PPO training").

For each run folder of occlusion_train_ppo, reads RUN/updates.csv and prints a Markdown row: the
median environment steps per second over the updates from --from-update on (the first updates
load the scenes' meshes), each update's rate being its steps over its wall time, and the shares
of that wall time spent stepping the environments, in inference and in optimisation. With one
libtorch thread (the trainer's default) each environment's thread encodes its own observation,
so the encoder's time is in the environments' share and inference is the heads alone.

  scripts/ppo_rate.py runs/a runs/b --from-update 4
"""
import argparse
import csv
import os
import statistics
import sys


def rate_row(label, run, first_update):
    path = os.path.join(run, "updates.csv")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    rates, env, inference, optimisation, total = [], 0.0, 0.0, 0.0, 0.0
    for previous, row in zip(rows, rows[1:]):
        if int(row["update"]) < first_update:
            continue
        seconds = float(row["seconds"]) - float(previous["seconds"])
        steps = int(row["env_steps"]) - int(previous["env_steps"])
        rates.append(steps / seconds)
        env += float(row["environment_seconds"])
        inference += float(row["inference_seconds"])
        optimisation += float(row["optimisation_seconds"])
        total += seconds
    if not rates:
        raise ValueError(f"{path}: no update from {first_update} on")
    return (f"| {label} | {statistics.median(rates):.0f} | {100 * env / total:.0f} % "
            f"| {100 * inference / total:.0f} % | {100 * optimisation / total:.0f} % "
            f"| {len(rates)} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", help="occlusion_train_ppo output folders")
    parser.add_argument("--from-update", type=int, default=6,
                        help="first update counted (default 6)")
    parser.add_argument("--label", action="append", default=[],
                        help="a row's label, one per run in order (default: the folder)")
    parser.add_argument("--no-header", action="store_true", help="rows only")
    args = parser.parse_args()
    if args.label and len(args.label) != len(args.runs):
        parser.error("give one --label per run, or none")
    labels = args.label or args.runs
    if not args.no_header:
        print("| run | steps/s (median) | environments | inference | optimisation | updates |")
        print("|---|---:|---:|---:|---:|---:|")
    try:
        for label, run in zip(labels, args.runs):
            print(rate_row(label, run, args.from_update))
    except (OSError, KeyError, ValueError) as error:
        print(f"ppo_rate.py: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
