#!/usr/bin/python3
"""Plots of an occlusion_eval run (PNG): box plots of steps per agent, the BEST posterior of each
pairwise mean difference (the paper's Figure A1 style) and the start-azimuth sweep (Figure 5; a
sweep over several models gets one panel per model, named from the <sweep>_models.csv beside it).

Usage: plot_evaluation.py --out DIR [--prefix P] [--episodes SET_episodes.csv] [--posterior best_mu_samples.csv
       --comparisons best_pairs.csv] [--sweep sweep_two_chairs.csv ...]
Needs python3-matplotlib (scripts/install_deps.sh).
"""
import argparse
import csv
import math
import os
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def counted_steps(row):
    """A failed episode counts as the step limit, as in the summary."""
    return int(row["steps"]) if row["success"] == "1" else int(row["max_steps"])


def by_agent(rows):
    groups = OrderedDict()
    for row in rows:
        groups.setdefault(row["agent"], []).append(row)
    return groups


def plot_boxplot(episodes_csv, out_dir, prefix):
    groups = by_agent(read_rows(episodes_csv))
    labels = list(groups)
    data = [[counted_steps(r) for r in groups[a]] for a in labels]
    fig, ax = plt.subplots(figsize=(1.8 + 1.6 * len(labels), 4.2))
    ax.boxplot(data, labels=labels, showmeans=True, meanline=True)
    for i, agent in enumerate(labels, start=1):
        failed = sum(r["success"] != "1" for r in groups[agent])
        ax.annotate(f"n={len(data[i - 1])}, failed={failed}", (i, 0), xytext=(0, -28),
                    textcoords="offset points", ha="center", fontsize=8,
                    annotation_clip=False)
    scene_set = data and groups[labels[0]][0]["scene_set"]
    ax.set_title(f"Steps to an unoccluded view ({scene_set})")
    ax.set_ylabel("steps (failures counted as the step limit)")
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    path = os.path.join(out_dir, f"{prefix}steps_boxplot.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return [path]


def plot_posteriors(posterior_csv, comparisons_csv, out_dir, prefix):
    samples = OrderedDict()
    for row in read_rows(posterior_csv):
        samples.setdefault((row["first"], row["second"]), []).append(float(row["mu"]))
    figures = {(r["first"], r["second"]): r for r in read_rows(comparisons_csv)}
    pairs = [p for p in figures if p in samples]
    if not pairs:
        return []
    cols = min(3, len(pairs))
    rows = math.ceil(len(pairs) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.4 * rows), squeeze=False)
    for ax, pair in zip(axes.flat, pairs):
        mu = samples[pair]
        stats = figures[pair]
        low, high = float(stats["mu_hdi_low"]), float(stats["mu_hdi_high"])
        mean = float(stats["mu_mean"])
        prob = 100.0 * float(stats["probability_second_fewer_steps"])
        ax.hist(mu, bins=60, color="#87ceeb", edgecolor="none", density=True)
        ymax = ax.get_ylim()[1]
        ax.plot([low, high], [0.05 * ymax, 0.05 * ymax], color="black", linewidth=4)
        ax.text(low, 0.1 * ymax, f"{low:.2f}", ha="right", fontsize=8)
        ax.text(high, 0.1 * ymax, f"{high:.2f}", ha="left", fontsize=8)
        ax.text((low + high) / 2, 0.18 * ymax, "95% HDI", ha="center", fontsize=8)
        ax.axvline(mean, color="navy", linewidth=1)
        # Zero (no difference) is marked only where it lies near the posterior.
        span = max(mu) - min(mu)
        if min(mu) - 0.5 * span <= 0.0 <= max(mu) + 0.5 * span:
            ax.axvline(0.0, color="green", linestyle=":", linewidth=1)
        ax.set_title(f"{pair[0]} - {pair[1]}\nmean = {mean:.2f}, "
                     f"P(mu < 0) = {100 - prob:.1f}%, P(mu > 0) = {prob:.1f}%", fontsize=9)
        ax.set_xlabel("mu (difference of mean steps)")
        ax.set_yticks([])
    for ax in list(axes.flat)[len(pairs):]:
        ax.axis("off")
    fig.suptitle("BEST posterior of mu, the paired mean difference of steps", fontsize=10)
    fig.tight_layout()
    path = os.path.join(out_dir, f"{prefix}best_posteriors.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return [path]


def plot_sweep(sweep_csv, out_dir):
    """Steps per start azimuth and agent; one panel per model when the sweep has several."""
    rows = read_rows(sweep_csv)
    scene_set = rows[0]["scene_set"] if rows else "sweep"
    seeds = list(OrderedDict.fromkeys(r["scene_seed"] for r in rows))
    if len(seeds) > 1:
        return plot_sweep_models(rows, seeds, sweep_csv, out_dir)
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    plot_sweep_lines(ax, by_agent(rows), agent_colours(rows), with_labels=True, markersize=6)
    ax.set_xlabel("start azimuth [deg]")
    ax.set_ylabel("steps to an unoccluded view")
    ax.set_title(f"Start-azimuth sweep: {scene_set.replace('sweep_', '')}")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(out_dir, f"{scene_set}.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return [path]


def agent_colours(rows):
    """Each agent's colour of the default cycle, by first appearance: the same in every panel.
    The oracle (a reference, not a competitor) is black."""
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    competitors = [a for a in by_agent(rows) if a != "oracle"]
    colours = {agent: cycle[k % len(cycle)] for k, agent in enumerate(competitors)}
    if any(r["agent"] == "oracle" for r in rows):
        colours["oracle"] = "black"
    return colours


def line_style(agent):
    return "--" if agent == "oracle" else "-"


def plot_sweep_lines(ax, groups, colours, with_labels, markersize):
    """One line per agent (counted steps over the start azimuth [deg]), a cross at each failure."""
    for agent, agent_rows in groups.items():
        agent_rows = sorted(agent_rows, key=lambda r: float(r["start_azimuth_rad"]))
        x = [math.degrees(float(r["start_azimuth_rad"])) for r in agent_rows]
        y = [counted_steps(r) for r in agent_rows]
        ax.plot(x, y, marker="o", markersize=markersize, color=colours[agent],
                linestyle=line_style(agent), label=agent if with_labels else None)
        failed = [(xi, yi) for xi, yi, r in zip(x, y, agent_rows) if r["success"] != "1"]
        if failed:
            ax.scatter(*zip(*failed), marker="x", s=60, color=colours[agent],
                       label=f"{agent}: failed (step limit)" if with_labels else None)


def plot_sweep_models(rows, seeds, sweep_csv, out_dir):
    """A sweep over several models (scene seeds): one small panel per model, titled from the
    models CSV written beside the sweep (<sweep>_models.csv) when there is one, and a last panel
    with each agent's mean over the models. Log steps: failures sit at the limit, far above."""
    scene_set = rows[0]["scene_set"]
    models_csv = os.path.splitext(sweep_csv)[0] + "_models.csv"
    names = {}
    if os.path.exists(models_csv):
        names = {r["seed"]: f"{r['name']} ({r['split']})" for r in read_rows(models_csv)}
    max_steps = max(int(r["max_steps"]) for r in rows)
    highest = max(counted_steps(r) for r in rows)  # the limit only when some episode failed
    panels = len(seeds) + 1
    cols = 3 if panels + 1 <= 6 else 4  # a free cell for the legend where it fits
    grid_rows = math.ceil(panels / cols)
    fig, axes = plt.subplots(grid_rows, cols, figsize=(4.2 * cols, 3.2 * grid_rows),
                             sharex=True, sharey=True, squeeze=False)
    flat = list(axes.flat)
    colours = agent_colours(rows)
    for k, (ax, seed) in enumerate(zip(flat, seeds)):
        plot_sweep_lines(ax, by_agent([r for r in rows if r["scene_seed"] == seed]), colours,
                         with_labels=False, markersize=3)
        ax.set_title(f"model {k + 1}: {names.get(seed, 'seed ' + seed)}", fontsize=9)
    # The mean over the models of each agent's counted steps, per start azimuth.
    mean_ax = flat[len(seeds)]
    for agent, agent_rows in by_agent(rows).items():
        per_azimuth = OrderedDict()
        for r in sorted(agent_rows, key=lambda r: float(r["start_azimuth_rad"])):
            per_azimuth.setdefault(float(r["start_azimuth_rad"]), []).append(counted_steps(r))
        x = [math.degrees(a) for a in per_azimuth]
        y = [sum(v) / len(v) for v in per_azimuth.values()]
        mean_ax.plot(x, y, marker="o", markersize=3, linewidth=2, color=colours[agent],
                     linestyle=line_style(agent))
    mean_ax.set_title(f"mean over the {len(seeds)} models", fontsize=9)
    for ax in flat[:panels]:
        ax.set_yscale("log")
        ax.set_ylim(0.8, highest * 1.6)
        ax.grid(alpha=0.3, which="both")
    for ax in axes[-1]:
        ax.set_xlabel("start azimuth [deg]")
    for ax in axes[:, 0]:
        ax.set_ylabel("steps (log)")
    for ax in flat[panels:]:
        ax.axis("off")
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=c, marker="o", markersize=3, linestyle=line_style(a), label=a)
               for a, c in colours.items()]
    handles.append(Line2D([], [], color="black", marker="x", linestyle="none", markersize=8,
                          label="failed (step limit)"))
    legend_ax = flat[panels] if panels < len(flat) else flat[len(seeds)]
    legend_ax.legend(handles=handles, fontsize=8, loc="center")
    fig.suptitle(f"Start-azimuth sweep: {scene_set.replace('sweep_', '')} "
                 f"(at most {max_steps} steps; x = failed)", fontsize=10)
    fig.tight_layout()
    path = os.path.join(out_dir, f"{scene_set}.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return [path]


def plot_landscape(landscape_csv, paths_csv, out_dir):
    """L over the camera angles, the unoccluded region outlined, each agent's path on top."""
    import numpy as np
    from matplotlib.colors import PowerNorm

    rows = read_rows(landscape_csv)
    azimuths = sorted({float(r["azimuth_rad"]) for r in rows})
    elevations = sorted({float(r["elevation_rad"]) for r in rows})
    a_index = {a: i for i, a in enumerate(azimuths)}
    e_index = {e: i for i, e in enumerate(elevations)}
    occlusion = np.zeros((len(elevations), len(azimuths)))
    for r in rows:
        occlusion[e_index[float(r["elevation_rad"])], a_index[float(r["azimuth_rad"])]] = \
            float(r["occlusion_px"])
    a_deg = np.degrees(azimuths)
    e_deg = np.degrees(elevations)

    fig, ax = plt.subplots(figsize=(7.2, 4.8))
    mesh = ax.pcolormesh(a_deg, e_deg, occlusion, shading="nearest", cmap="magma",
                         norm=PowerNorm(0.4, vmin=0, vmax=max(1.0, occlusion.max())))
    fig.colorbar(mesh, ax=ax, label="occlusion L [px]")
    if (occlusion == 0).any() and (occlusion > 0).any():
        ax.contour(a_deg, e_deg, (occlusion == 0).astype(float), levels=[0.5],
                   colors="cyan", linewidths=1.0)
    paths = by_agent(read_rows(paths_csv))
    colours = ["#4fc3f7", "#ffffff", "#a5d6a7", "#ffcc80"]
    for k, (agent, agent_rows) in enumerate(paths.items()):
        agent_rows.sort(key=lambda r: int(r["t"]))
        x = [math.degrees(float(r["azimuth_rad"])) for r in agent_rows]
        y = [math.degrees(float(r["elevation_rad"])) for r in agent_rows]
        colour = colours[k % len(colours)]
        success = agent_rows[0]["success"] == "1"
        steps = agent_rows[0]["steps"]
        ax.plot(x, y, "-", color=colour, linewidth=1.4, marker=".", markersize=3,
                label=f"{agent}: {steps} steps, {'unoccluded' if success else 'failed'}")
        ax.plot(x[0], y[0], "o", color=colour, markersize=7, markeredgecolor="black")
        ax.plot(x[-1], y[-1], "*" if success else "X", color=colour, markersize=12,
                markeredgecolor="black")
    ax.set_xlabel("azimuth [deg]")
    ax.set_ylabel("elevation [deg]")
    ax.set_title("Occlusion over the camera angles, and each agent's path")
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    stem = os.path.splitext(os.path.basename(landscape_csv))[0]
    path = os.path.join(out_dir, f"{stem}.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return [path]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True)
    parser.add_argument("--prefix", default="", help="file name prefix of the PNGs")
    parser.add_argument("--episodes")
    parser.add_argument("--posterior")
    parser.add_argument("--comparisons")
    parser.add_argument("--sweep", action="append", default=[])
    parser.add_argument("--landscape", help="CSV of occlusion over camera angles")
    parser.add_argument("--paths", help="CSV of the agents' paths on the landscape")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    written = []
    if args.episodes:
        written += plot_boxplot(args.episodes, args.out, args.prefix)
    if args.posterior and args.comparisons:
        written += plot_posteriors(args.posterior, args.comparisons, args.out, args.prefix)
    for sweep in args.sweep:
        written += plot_sweep(sweep, args.out)
    if args.landscape and args.paths:
        written += plot_landscape(args.landscape, args.paths, args.out)
    for path in written:
        print(path)


if __name__ == "__main__":
    main()
