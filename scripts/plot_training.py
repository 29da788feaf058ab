#!/usr/bin/env python3
"""Training curves of occlusion_train: reads RUN_DIR/log.csv, writes RUN_DIR/curves.png.
Usage: plot_training.py RUN_DIR/log.csv"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("plot_training: no epochs in " + sys.argv[1])
    epoch = [int(r["epoch"]) for r in rows]
    col = lambda name: [float(r[name]) for r in rows]  # noqa: E731
    # Columns that later versions added: absent from older logs, 0 where they do not apply.
    optional = lambda name: (  # noqa: E731
        col(name) if name in rows[0] and any(float(r[name]) > 0 for r in rows) else None)
    shares = [(name, optional(column)) for name, column in (
        ("escape head", "val_escape_shortest_share"),
        ("escape bins' choice", "val_escape_bins_shortest_share"))]
    shares = [(name, share) for name, share in shares if share]
    fig, axes = plt.subplots(1, 4 if shares else 3, figsize=(17 if shares else 13, 3.6))
    axes[0].plot(epoch, col("train_loss"), label="train loss (Eq. 12)")
    axes[0].plot(epoch, col("val_dice_loss"), label="val soft Dice loss")
    axes[0].set_xlabel("epoch")
    axes[0].legend()
    axes[1].plot(epoch, [100 * v for v in col("val_iou")], label="val IoU of the occlusion map")
    axes[1].set_xlabel("epoch")
    axes[1].set_ylabel("%")
    axes[1].legend()
    axes[2].plot(epoch, col("val_gradient_angle_deg"), label="gradient direction")
    axes[2].plot(epoch, col("val_escape_angle_deg"), label="escape direction")
    bins = optional("val_escape_bins_angle_deg")
    if bins:
        axes[2].plot(epoch, bins, label="escape bins' choice")
    axes[2].set_xlabel("epoch")
    axes[2].set_ylabel("mean angular error [deg]")
    axes[2].legend()
    for name, share in shares:
        axes[3].plot(epoch, [100 * v for v in share], label=name)
    if shares:
        axes[3].set_xlabel("epoch")
        axes[3].set_ylabel("% of validation moves")
        axes[3].set_title("moves as short as the oracle's", fontsize="medium")
        axes[3].legend()
    fig.suptitle(os.path.dirname(os.path.abspath(sys.argv[1])))
    fig.tight_layout()
    out = os.path.join(os.path.dirname(sys.argv[1]) or ".", "curves.png")
    fig.savefig(out, dpi=110)
    print("plot_training: wrote", out)


if __name__ == "__main__":
    main()
