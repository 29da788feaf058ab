#!/usr/bin/env python3
"""Validation IoU and escape-direction error per epoch of every run in doc/training/ (the logs
that scripts/train_table3.sh copies there), one line per run, in one PNG.
Usage: plot_table3.py [TRAINING_DIR] (default: doc/training of the source tree)"""
import csv
import glob
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    folder = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "doc", "training")
    logs = sorted(glob.glob(os.path.join(folder, "*.csv")))
    if not logs:
        sys.exit("plot_table3: no *.csv in " + folder)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    for path in logs:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        name = os.path.splitext(os.path.basename(path))[0]
        epochs = [int(r["epoch"]) for r in rows]
        axes[0].plot(epochs, [100 * float(r["val_iou"]) for r in rows], marker=".", label=name)
        axes[1].plot(epochs, [float(r["val_escape_angle_deg"]) for r in rows], marker=".",
                     label=name)
    axes[0].set_ylabel("validation IoU of the occlusion map [%]")
    axes[1].set_ylabel("escape direction: mean angular error [deg]")
    for ax in axes:
        ax.set_xlabel("epoch")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    out = os.path.join(folder, "iou_per_epoch.png")
    fig.savefig(out, dpi=110)
    print("plot_table3: wrote " + out)


if __name__ == "__main__":
    main()
