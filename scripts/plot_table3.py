#!/usr/bin/env python3
"""Validation IoU and escape-direction error of every run in doc/training/ (the logs and manifests
that scripts/train_table3.sh copies there) over the training images seen, one line per run. A
warm restart (--init-from) starts where its starting model's run stood at the epoch it was taken
from, joined to it, so a chain of restarts reads as one curve; the paper's best IoU is a line.
Usage: plot_table3.py [TRAINING_DIR] (default: doc/training of the source tree)"""
import csv
import glob
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def dataset_train_frames(manifest):
    """Training frames of a manifest without train_frames (older ones), from its dataset.json."""
    dataset = os.path.join(ROOT, manifest["dataset"], "dataset.json")
    if not os.path.exists(dataset):
        sys.exit("plot_table3: no train_frames in a manifest and no " + dataset + " to count")
    with open(dataset) as f:
        scenes = json.load(f)["scenes"]
    frames = manifest["dataset_options"]["frames"]
    return frames * sum(1 for scene in scenes if scene["split"] == "train")


PAPER_BEST_IOU = 62.37  # SAR-UNet-L1, Table 3 of the paper [%]


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "doc", "training")
    logs = sorted(glob.glob(os.path.join(folder, "*.csv")))
    if not logs:
        sys.exit("plot_table3: no *.csv in " + folder)
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5))
    colours = plt.get_cmap("tab20").colors
    for index, path in enumerate(logs):
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        name = os.path.splitext(os.path.basename(path))[0]
        with open(os.path.splitext(path)[0] + ".json") as f:
            manifest = json.load(f)
        frames = manifest.get("train_frames") or dataset_train_frames(manifest)
        # A warm restart is drawn on from its starting model's epoch (record_run.py's figures).
        start = manifest.get("initialised_from", {})
        offset = start.get("images_before", 0) / 1e6
        seen = [offset + int(r["epoch"]) * frames / 1e6 for r in rows]
        iou = [100 * float(r["val_iou"]) for r in rows]
        angle = [float(r["val_escape_angle_deg"]) for r in rows]
        if "images_before" in start:
            seen = [offset] + seen
            iou = [100 * start["validation"]["val_iou"]] + iou
            angle = [start["validation"]["val_escape_angle_deg"]] + angle
        style = dict(marker=".", color=colours[index % len(colours)],
                     linestyle="--" if start else "-")
        axes[0].plot(seen, iou, label=name, **style)
        axes[1].plot(seen, angle, **style)
    axes[0].axhline(PAPER_BEST_IOU, color="black", linewidth=0.8, linestyle=":",
                    label="paper's best (62.37 %, 256 px)")
    axes[0].set_ylabel("validation IoU of the occlusion map [%]")
    axes[1].set_ylabel("escape direction: mean angular error [deg]")
    for ax in axes:
        ax.set_xlabel("training images seen [millions] (a marker per epoch; dashed: warm restart)")
        ax.grid(alpha=0.3)
    fig.legend(*axes[0].get_legend_handles_labels(), loc="lower center", ncol=3, fontsize=8)
    fig.tight_layout(rect=(0, 0.22, 1, 1))
    out = os.path.join(folder, "iou_per_epoch.png")
    fig.savefig(out, dpi=110)
    print("plot_table3: wrote " + out)


if __name__ == "__main__":
    main()
