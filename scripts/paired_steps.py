#!/usr/bin/env python3
"""Compares agents' episodes scene by scene: for each episode CSV (agents/episode.hpp, versions 1
and 2; or a folder holding one *_episodes.csv, as occlusion_eval --out writes) the mean steps with
failures counted at the step limit, the successes, and the mean paired difference to the first
CSV with its standard error (the spread of the per-scene differences / sqrt(n)). Episodes pair
by scene seed and start azimuth; every CSV must hold the same episodes. With --reference (e.g.
the oracle's episodes on the same scenes) each mean is also given as a ratio to the reference's.
With --turn-backs DEG, how often an agent turns back: the moves of its paths (version 2's
azimuths_rad and elevations_rad, the azimuth step scaled by the cosine of the elevation it starts
from) that turn more than DEG degrees from the move before, and the episodes that hold one.

Usage: paired_steps.py BASE OTHER [OTHER ...] [--agent NAME] [--reference CSV] [--turn-backs DEG]
  BASE, OTHER   episode CSVs or occlusion_eval output folders
  --agent NAME  use this agent's rows (needed when a CSV holds several agents)
  --reference   a CSV or folder whose mean the ratios divide by (its own --agent: the first agent)
  --turn-backs  the angle [deg] beyond which a move counts as turning back (e.g. 120)
Prints a Markdown table; exits 1 on unreadable or mismatched input."""
import argparse
import csv
import glob
import math
import os
import sys
from statistics import mean, stdev


class InputError(Exception):
    pass


def episode_csv(path):
    if os.path.isdir(path):
        found = sorted(glob.glob(os.path.join(path, "*_episodes.csv")))
        if len(found) != 1:
            raise InputError(f"{path}: expected one *_episodes.csv, found {len(found)}")
        return found[0]
    if not os.path.isfile(path):
        raise InputError(f"{path}: no such file or folder")
    return path


def agent_rows(path, agent):
    """The rows of `agent` (the CSV's only agent when None) in the episode CSV at `path`."""
    path = episode_csv(path)
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise InputError(f"{path}: no episodes")
    agents = sorted({row["agent"] for row in rows})
    if agent is None:
        if len(agents) > 1:
            raise InputError(f"{path} holds several agents ({', '.join(agents)}): give --agent")
        agent = agents[0]
    rows = [row for row in rows if row["agent"] == agent]
    if not rows:
        raise InputError(f"{path}: no episodes of agent {agent!r} (it has {', '.join(agents)})")
    return path, rows


def counted_steps(path, agent):
    """{(scene_seed, start_azimuth_rad): (counted steps, success)} of `agent`'s rows."""
    path, rows = agent_rows(path, agent)
    episodes = {}
    for row in rows:
        success = row["success"] == "1"
        steps = int(row["steps"]) if success else int(row["max_steps"])
        key = (int(row["scene_seed"]), float(row["start_azimuth_rad"]))
        if key in episodes:
            raise InputError(f"{path}: scene {key[0]} at azimuth {key[1]} appears twice")
        episodes[key] = (steps, success)
    return episodes


def turn_backs(path, agent, degrees):
    """(moves turning more than `degrees` from the one before, moves after a first one,
    episodes holding such a move) over `agent`'s paths."""
    path, rows = agent_rows(path, agent)
    limit = math.cos(math.radians(degrees))
    turned = counted = episodes = 0
    for row in rows:
        if not row.get("azimuths_rad") or not row.get("elevations_rad"):
            raise InputError(f"{path}: --turn-backs needs the paths of version 2's episode CSVs")
        azimuths = [float(a) for a in row["azimuths_rad"].split(";")]
        elevations = [float(e) for e in row["elevations_rad"].split(";")]
        moves = [((azimuths[i + 1] - azimuths[i]) * math.cos(elevations[i]),
                  elevations[i + 1] - elevations[i]) for i in range(len(azimuths) - 1)]
        moves = [(x, y) for x, y in moves if math.hypot(x, y) > 0.0]
        any_turned = False
        for (x0, y0), (x1, y1) in zip(moves, moves[1:]):
            counted += 1
            if (x0 * x1 + y0 * y1) / (math.hypot(x0, y0) * math.hypot(x1, y1)) < limit:
                turned += 1
                any_turned = True
        episodes += any_turned
    return turned, counted, episodes


# The bins of --spread: (label, lowest difference, highest difference) in steps.
SPREAD_BINS = [("< 0", -math.inf, -1), ("0", 0, 0), ("+1", 1, 1), ("+2", 2, 2), ("+3", 3, 3),
               ("+4-5", 4, 5), ("+6-9", 6, 9), ("+10 or more", 10, math.inf)]
# --spread's "long" scenes: at least this many steps more than the first run's.
SPREAD_LONG = 4


def spread(differences):
    """(scenes per SPREAD_BINS bin, the share of the summed positive differences held by scenes
    SPREAD_LONG or more steps apart; NaN when no scene is apart)."""
    counts = [sum(low <= d <= high for d in differences) for _, low, high in SPREAD_BINS]
    positive = sum(d for d in differences if d > 0)
    long_share = (sum(d for d in differences if d >= SPREAD_LONG) / positive
                  if positive > 0 else float("nan"))
    return counts, long_share


def standard_error(values):
    """Of the mean: the sample standard deviation / sqrt(n)."""
    if len(values) < 2:
        return float("nan")
    return stdev(values) / math.sqrt(len(values))


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--agent", action="append", default=[])
    parser.add_argument("--reference")
    parser.add_argument("--turn-backs", type=float, metavar="DEG")
    parser.add_argument("--spread", action="store_true")
    args = parser.parse_args(argv)
    if len(args.runs) < 2:
        parser.error("give a base and at least one other run")
    if len(args.agent) not in (0, 1, len(args.runs)):
        parser.error(f"give --agent once, or once per run ({len(args.runs)}), not "
                     f"{len(args.agent)} times")
    per_run = len(args.agent) == len(args.runs)
    agents = args.agent if per_run else (args.agent or [None]) * len(args.runs)
    try:
        # Rows are named by the run, and by the agent too when each run has its own.
        runs = [(f"{path} ({agent})" if per_run else path, counted_steps(path, agent))
                for path, agent in zip(args.runs, agents)]
        reference = counted_steps(args.reference, None) if args.reference else None
        keys = sorted(runs[0][1])
        for path, episodes in runs[1:] + ([(args.reference, reference)] if reference else []):
            if sorted(episodes) != keys:
                raise InputError(f"{path} and {args.runs[0]} hold different episodes "
                                 f"({len(episodes)} and {len(keys)}): pairs need the same scenes")
        turns = ([turn_backs(path, agent, args.turn_backs)
                  for path, agent in zip(args.runs, agents)]
                 if args.turn_backs is not None else None)
    except (InputError, KeyError, ValueError) as error:
        print(f"paired_steps.py: {error}", file=sys.stderr)
        return 1
    base = [runs[0][1][k][0] for k in keys]
    reference_mean = mean([reference[k][0] for k in keys]) if reference else None
    header = "| run | episodes | successes | mean steps | against the first |"
    rule = "|---|---:|---:|---:|---:|"
    if reference_mean:
        header += " ratio to the reference |"
        rule += "---:|"
    if turns:
        header += f" moves turning back > {args.turn_backs:g} deg (episodes) |"
        rule += "---:|"
    print(header)
    print(rule)
    for index, (path, episodes) in enumerate(runs):
        steps = [episodes[k][0] for k in keys]
        successes = sum(episodes[k][1] for k in keys)
        if index == 0:
            against = ""
        else:
            differences = [s - b for s, b in zip(steps, base)]
            against = f"{mean(differences):+.2f} ± {standard_error(differences):.2f}"
        line = f"| {path} | {len(keys)} | {successes} | {mean(steps):.2f} | {against} |"
        if reference_mean:
            line += f" {mean(steps) / reference_mean:.3f} |"
        if turns:
            turned, counted, episodes_turning = turns[index]
            line += f" {turned} of {counted} ({episodes_turning}) |"
        print(line)
    if reference_mean:
        print(f"\nreference {args.reference}: {reference_mean:.2f} steps")
    if args.spread:
        print(f"\nScenes by their difference to {runs[0][0]} [steps]:\n")
        print("| run | " + " | ".join(label for label, _, _ in SPREAD_BINS) +
              f" | of the summed excess, at +{SPREAD_LONG} or more |")
        print("|---|" + "---:|" * (len(SPREAD_BINS) + 1))
        for path, episodes in runs[1:]:
            counts, long_share = spread([episodes[k][0] - b for k, b in zip(keys, base)])
            share = "-" if math.isnan(long_share) else f"{100 * long_share:.0f} %"
            print(f"| {path} | " + " | ".join(map(str, counts)) + f" | {share} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
