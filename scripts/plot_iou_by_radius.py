#!/usr/bin/env python3
"""A model's occlusion IoU by the camera's distance from the scene, one line per depth sensor.
Reads `occlusion_train --check` JSON files, each of one dataset made with `--randomize
--radius-range A,B --depth-sensor S`; the sensor, the world and the radius range come from that
dataset's dataset.json (its options). Prints a Markdown table (IoU % and its 95 % interval over
scenes) and, with --out, draws it: where a sensor stops reading the nearer objects
(doc/TRAINING.md, "Where the last 6 points go").

Usage: scripts/plot_iou_by_radius.py CHECK.json [CHECK.json ...] [--out FIGURE.png]
  e.g. scripts/plot_iou_by_radius.py runs/radius_checks/*.json --out iou_by_radius.png
"""
import argparse
import json
import os
import sys
from collections import defaultdict


def point(check_path):
    """(model, world, depth sensor, radius range (lo, hi) [m], IoU, (low, high)) of a check."""
    with open(check_path) as f:
        check = json.load(f)
    datasets = check.get("datasets") or []
    if len(datasets) != 1:
        sys.exit("plot_iou_by_radius: %s checks %d datasets; give checks of one each"
                 % (check_path, len(datasets)))
    manifest_path = os.path.join(datasets[0], "dataset.json")
    try:
        with open(manifest_path) as f:
            options = json.load(f)["options"]
    except (OSError, KeyError, ValueError) as error:
        sys.exit("plot_iou_by_radius: %s: cannot read its dataset's options (%s)"
                 % (check_path, error))
    radius = (options.get("camera_randomization") or {}).get("radius_range")
    if not options.get("randomize") or not radius:
        sys.exit("plot_iou_by_radius: %s was not made with --randomize: no radius range"
                 % datasets[0])
    figures = check["figures"]
    low, high = figures["val_iou_95"]
    return (check.get("model", "?"), options.get("world") or "random",
            options.get("depth_sensor") or "random", tuple(radius), figures["val_iou"],
            (low, high))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("checks", nargs="+", metavar="CHECK.json",
                        help="occlusion_train --check output, one dataset each")
    parser.add_argument("--out", help="also draw the figure here (PNG)")
    args = parser.parse_args()
    series = defaultdict(list)  # (world, sensor) -> [(radius range, IoU, interval)]
    models = set()
    for path in args.checks:
        model, world, sensor, radius, iou, interval = point(path)
        models.add(model)
        series[(world, sensor)].append((radius, iou, interval))
    if len(models) != 1:
        sys.exit("plot_iou_by_radius: the checks are of %d models (%s); give one model's"
                 % (len(models), ", ".join(sorted(models))))
    for points in series.values():
        points.sort()
    ranges = sorted({radius for points in series.values() for radius, _, _ in points})
    print("| world, depth sensor | " + " | ".join("%g-%g m" % r for r in ranges) + " |")
    print("|---|" + "---:|" * len(ranges))
    for (world, sensor), points in sorted(series.items()):
        by_range = {radius: (iou, interval) for radius, iou, interval in points}
        cells = ["%.1f (%.1f-%.1f)" % (100 * by_range[r][0], 100 * by_range[r][1][0],
                                       100 * by_range[r][1][1]) if r in by_range else ""
                 for r in ranges]
        print("| %s, %s | %s |" % (world, sensor, " | ".join(cells)))
    if not args.out:
        return
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axis = plt.subplots(figsize=(6.4, 4.2))
    for (world, sensor), points in sorted(series.items()):
        middles = [(lo + hi) / 2 for (lo, hi), _, _ in points]
        ious = [100 * iou for _, iou, _ in points]
        errors = [[100 * (iou - low) for _, iou, (low, _) in points],
                  [100 * (high - iou) for _, iou, (_, high) in points]]
        axis.errorbar(middles, ious, yerr=errors, marker="o", capsize=3,
                      label="%s, %s" % (world, sensor))
    axis.set_title(models.pop(), fontsize=9)
    axis.set_xlabel("camera's distance from the scene's centre [m]")
    axis.set_ylabel("occlusion IoU [%] (95 % over scenes)")
    axis.grid(alpha=0.3)
    axis.legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print("plot_iou_by_radius: wrote " + args.out)


if __name__ == "__main__":
    main()
