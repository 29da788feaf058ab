#!/usr/bin/env python3
"""Studies stopping rules that occlusion_bridge_calibration does not print, on the views it
writes with --views-csv (seed, step, the true occlusion and the estimate at each probability, in
px). A level (p, t, k) stops an episode at the first step view that is the k-th in a row (the
start view never counts) whose estimate at probability p is at most t px; a rule of two levels
stops at whichever comes first: e.g. (0.01, 0, 1) + (0.2, 0, 5) stops at once on a view with no
pixel above 0.01, and otherwise after five views clear at 0.2. The bridge's own rule is one level.

With --also, the views of a second estimate on the same paths (occlusion_bridge_calibration run
with the same agent, scenes and world, another --model): rules of one level that count a view
clear only when both estimates are, each at its own probability and threshold, are tried too
(written (p, t) & (q, u) px, k views).

Rules are chosen on CHOOSE (the fewest mean steps among those stopping on a truly clear view in at
least --need of its scenes) and shown on CHECK, other validation scenes, beside the one-level
rule given with --baseline. Episodes that never stop count at --max-steps. With --one-level only
the rules the bridge can run are tried (one level, one estimate). CHOOSE may hold the views of
several calibration runs of other seeds one after the other (one header line).

Then, at the baseline's probability and threshold, how often the estimate calls a truly clear
view occluded, by how many views the path had already been truly clear before it (0: the first
clear view after an occluded one): what the confirming views pay for.

Usage: stopping_rules.py CHOOSE.csv [CHECK.csv] [--need 0.95] [--baseline 0.2,0,5] [--top 10]
                         [--also CHOOSE2.csv[,CHECK2.csv] | --one-level]
Exits 1 on unreadable input or a second estimate's views of other paths."""
import argparse
import csv
import itertools
import sys
from collections import OrderedDict

PREFIX = "estimated_px_at_"


def load(path):
    """{seed: [(true_px, {probability: estimated_px}), ...]} and the probabilities, as written."""
    paths = OrderedDict()
    try:
        with open(path, newline="") as handle:
            reader = csv.DictReader(handle)
            probabilities = [name[len(PREFIX):] for name in reader.fieldnames or []
                             if name.startswith(PREFIX)]
            if not probabilities or "true_px" not in (reader.fieldnames or []):
                raise ValueError("not a --views-csv file")
            for row in reader:
                estimates = {p: int(row[PREFIX + p]) for p in probabilities}
                paths.setdefault(int(row["seed"]), []).append((int(row["true_px"]), estimates))
    except (OSError, ValueError, KeyError) as error:
        sys.exit(f"stopping_rules.py: {path}: {error}")
    if not paths:
        sys.exit(f"stopping_rules.py: {path}: no views")
    return paths, probabilities


SECOND = "also:"  # the key prefix of a second estimate's probabilities


def joined(paths, second, name):
    """paths with the estimates of `second` (the same paths' views) added under SECOND + p."""
    if sorted(paths) != sorted(second) or any(
            [true_px for true_px, _ in paths[seed]] != [true_px for true_px, _ in second[seed]]
            for seed in paths):
        sys.exit(f"stopping_rules.py: {name}: not the views of the same paths (seeds, steps and "
                 "true occlusion must match)")
    return OrderedDict(
        (seed, [(true_px, dict(estimates, **{SECOND + p: px for p, px in other.items()}))
                for (true_px, estimates), (_, other) in zip(views, second[seed])])
        for seed, views in paths.items())


def is_clear(estimates, probability, threshold):
    """A level's condition: one estimate (probability, threshold) or both ((p, t), (q, u))."""
    if isinstance(probability, tuple):
        return all(estimates[p] <= t for p, t in zip(probability, threshold))
    return estimates[probability] <= threshold


def stop_step(path, levels):
    """The step where the rule stops, or None."""
    in_a_row = [0] * len(levels)
    for step in range(1, len(path)):
        for i, (probability, threshold, views) in enumerate(levels):
            clear = is_clear(path[step][1], probability, threshold)
            in_a_row[i] = in_a_row[i] + 1 if clear else 0
            if in_a_row[i] >= views:
                return step
    return None


def score(paths, levels, max_steps):
    """(stops on a clear view, too early, never, mean steps to the stop)."""
    clear = early = never = 0
    steps = 0
    for path in paths.values():
        step = stop_step(path, levels)
        if step is None:
            never += 1
            steps += max_steps
        else:
            clear += path[step][0] == 0
            early += path[step][0] != 0
            steps += step
    return clear, early, never, steps / len(paths)


def false_alarms_by_clear_run(paths, probability, threshold, deepest=5):
    """[(truly clear views, of them estimated above threshold px)] by the views the path had been
    truly clear before each (0 .. deepest, the last also counting deeper ones)."""
    counts = [[0, 0] for _ in range(deepest + 1)]
    for path in paths.values():
        run = -1  # views truly clear before this one, -1 after an occluded view
        for step in range(1, len(path)):
            true_px, estimates = path[step]
            if true_px != 0:
                run = -1
                continue
            run += 1
            cell = counts[min(run, deepest)]
            cell[0] += 1
            cell[1] += estimates[probability] > threshold
    return counts


def describe(levels):
    def level(p, t, k):
        if isinstance(p, tuple):
            return f"({p[0]}, {t[0]}) & ({p[1][len(SECOND):]}, {t[1]}) px, {k} views"
        return f"({p}, {t}, {k})"
    return " + ".join(level(*entry) for entry in levels)


def show(counts):
    clear, early, never, steps = counts
    return f"{clear} / {early} / {never}, {steps:.2f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("choose")
    parser.add_argument("check", nargs="?")
    parser.add_argument("--need", type=float, default=0.95,
                        help="fraction of the scenes a rule must stop on a truly clear view")
    parser.add_argument("--baseline", default="0.2,0,5", help="the one-level rule p,t,k shown too")
    parser.add_argument("--thresholds", default="0,16", help="candidate thresholds t [px]")
    parser.add_argument("--views", default="1,2,3,4,5,6", help="candidate views in a row k")
    parser.add_argument("--max-steps", type=int, default=50)
    parser.add_argument("--top", type=int, default=10)
    parser.add_argument("--also", help="CHOOSE2.csv[,CHECK2.csv]: a second estimate's views of "
                        "the same paths; rules where both must call a view clear are tried too")
    parser.add_argument("--one-level", action="store_true",
                        help="try only one-level rules of one estimate, the bridge's own kind")
    args = parser.parse_args()
    if args.one_level and args.also:
        sys.exit("stopping_rules.py: --one-level tries one estimate's rules; --also adds another's")
    choose, probabilities = load(args.choose)
    check = None
    if args.check:
        check, check_probabilities = load(args.check)
        probabilities = [p for p in probabilities if p in check_probabilities]
    second_probabilities = []
    if args.also:
        second_files = args.also.split(",")
        if len(second_files) != (2 if check else 1):
            sys.exit("stopping_rules.py: --also needs one views CSV per input (CHOOSE2[,CHECK2])")
        second, second_probabilities = load(second_files[0])
        choose = joined(choose, second, second_files[0])
        if check:
            second_check, check_probabilities = load(second_files[1])
            second_probabilities = [p for p in second_probabilities if p in check_probabilities]
            check = joined(check, second_check, second_files[1])
    thresholds = [int(t) for t in args.thresholds.split(",")]
    views = [int(k) for k in args.views.split(",")]
    p, t, k = args.baseline.split(",")
    baseline = [(p, int(t), int(k))]
    if p not in probabilities:
        sys.exit(f"stopping_rules.py: the baseline's probability {p} is not in the CSV files")

    levels = [(p, t, k) for p in probabilities for t in thresholds for k in views]
    rules = [[level] for level in levels]
    if second_probabilities:
        # Both estimates clear, each at its own probability and threshold.
        rules += [[((p, SECOND + q), (t, u), k)]
                  for p in probabilities for q in second_probabilities
                  for t in thresholds for u in thresholds for k in views]
    elif not args.one_level:
        rules += [list(pair) for pair in itertools.combinations(levels, 2)
                  if pair[0][2] != pair[1][2]]
    chosen = []
    for rule in rules:
        counts = score(choose, rule, args.max_steps)
        if counts[0] >= args.need * len(choose):
            chosen.append((counts[3], rule, counts))
    chosen.sort(key=lambda entry: entry[0])

    def first_clear(paths):
        steps = [next((s for s in range(1, len(path)) if path[s][0] == 0), args.max_steps)
                 for path in paths.values()]
        return sum(steps) / len(steps)

    print(f"choose: {args.choose}, {len(choose)} scenes, the path's first truly clear view after "
          f"{first_clear(choose):.2f} steps")
    if check:
        print(f"check: {args.check}, {len(check)} scenes, first truly clear view after "
              f"{first_clear(check):.2f} steps")
    print("\n(stops on a clear view / too early / never, mean steps to the stop)\n")
    header = "| rule (p, t px, k views) | choose |" + (" check |" if check else "")
    print(header)
    print("|---|---|" + ("---|" if check else ""))
    for _, rule, counts in [(None, baseline, score(choose, baseline, args.max_steps))] + \
            chosen[:args.top]:
        line = f"| {describe(rule)} | {show(counts)} |"
        if check:
            line += f" {show(score(check, rule, args.max_steps))} |"
        print(line)

    p, t, _ = baseline[0]
    print(f"\n(truly clear views: estimated above {t} px at {p}, by views truly clear before)\n")
    print("| views clear before | choose |" + (" check |" if check else ""))
    print("|---:|---|" + ("---|" if check else ""))
    tables = [false_alarms_by_clear_run(paths, p, t) for paths in ([choose, check] if check
                                                                     else [choose])]
    for run in range(len(tables[0])):
        label = f"{run}" if run + 1 < len(tables[0]) else f">= {run}"
        cells = [f"{alarms} of {views}" + (f" ({100.0 * alarms / views:.0f} %)" if views else "")
                 for views, alarms in (table[run] for table in tables)]
        print(f"| {label} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
