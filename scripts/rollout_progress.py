#!/usr/bin/env python3
"""Where an agent's roll-outs lose steps against the oracle, from a DAgger set (occlusion_dagger):
every state there is labelled with the oracle's steps to an unoccluded view, so each of the
agent's moves either brings the oracle's count down by one (progress), leaves it (none), raises it
(regress) or brings it down by more than one (jump: the oracle counts whole steps on a lattice of
half steps, so a move can skip a count). Prints, per oracle count before the move, how the moves
went, and the roll-outs' moves against the oracle's steps from their start views.

Usage: scripts/rollout_progress.py DAGGER_SET [DAGGER_SET ...]   (e.g. runs/dagger/data_1)
"""
import collections
import glob
import json
import os
import sys

KINDS = ("progress", "none", "regress", "jump")


def kind(before, after):
    delta = after - before
    if delta == -1:
        return "progress"
    if delta == 0:
        return "none"
    return "regress" if delta > 0 else "jump"


def summarize(dataset):
    moves_by_count = collections.defaultdict(collections.Counter)
    rollouts = moves = start_steps = unfinished = 0
    for scene in sorted(glob.glob(os.path.join(dataset, "train", "*", "scene_labels.json"))):
        labels = json.load(open(scene))
        counts = [labels[k]["oracle_steps"] for k in sorted(labels, key=int)]
        if counts[-1] != 0:  # stopped at the step limit
            unfinished += 1
            continue
        rollouts += 1
        moves += len(counts) - 1
        start_steps += counts[0]
        for before, after in zip(counts, counts[1:]):
            moves_by_count[min(before, 8)][kind(before, after)] += 1
    if rollouts == 0:
        sys.exit(f"rollout_progress: no finished roll-out in {dataset}")
    print(f"{dataset}: {rollouts} roll-outs that reached an unoccluded view ({unfinished} did not); "
          f"{moves / rollouts:.2f} moves against the oracle's {start_steps / rollouts:.2f} steps "
          f"from the same start views ({moves / start_steps:.3f}x)\n")
    print("| oracle's steps before the move | moves per roll-out | progress | none | regress | jump |")
    print("|---:|---:|---:|---:|---:|---:|")
    for count in sorted(moves_by_count):
        c = moves_by_count[count]
        total = sum(c.values())
        shares = " | ".join(f"{100 * c[k] / total:.0f} %" for k in KINDS)
        label = f"{count}" if count < 8 else "8 or more"
        print(f"| {label} | {total / rollouts:.2f} | {shares} |")
    print()


def main(argv):
    if len(argv) < 2:
        sys.exit(__doc__)
    for dataset in argv[1:]:
        summarize(dataset)


if __name__ == "__main__":
    main(sys.argv)
