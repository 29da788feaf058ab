#!/usr/bin/env python3
"""Plots one episode of an agent in the in-process environment: the RGB and depth images of
chosen steps, the occlusion and the reward per step, the camera's path on its sphere.

    source .build_ws/devel/setup.bash
    python3 scripts/plot_episode.py --agent predicted_escape --seed 3 --out episode.png
    python3 scripts/plot_episode.py --agent random --size 128 --frames 6

Agents: occlusion_env.agents.names() (random, gradient, oracle, predicted_gradient,
predicted_escape, ...). Writes a PNG; no display needed.
"""

import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import occlusion_env  # noqa: E402
from occlusion_env import agents  # noqa: E402


def run_episode(agent_name, seed, size, max_steps):
    """Every observation (copies), reward and info of one episode."""
    env = occlusion_env.make(copy=True, width=size, height=size, max_steps=max_steps)
    agent = agents.load(agent_name, env=env)
    agent.reset(seed)
    observation, info = env.reset(seed=seed)
    frames, infos, rewards = [observation], [info], [0.0]
    done = False
    while not done:
        observation, reward, terminated, truncated, info = env.step(agent(observation))
        frames.append(observation)
        infos.append(info)
        rewards.append(reward)
        done = terminated or truncated
    env.close()
    return frames, infos, rewards, terminated


def plot(frames, infos, rewards, solved, columns, title, out):
    shown = np.unique(np.linspace(0, len(frames) - 1, columns).round().astype(int))
    figure = plt.figure(figsize=(2.4 * len(shown), 8.2))
    grid = figure.add_gridspec(3, len(shown), height_ratios=[1, 1, 1.3])
    for column, index in enumerate(shown):
        rgb_axes = figure.add_subplot(grid[0, column])
        rgb_axes.imshow(frames[index]["rgb"])
        rgb_axes.set_title(f"step {index}\nL = {infos[index]['occlusion_pixels']} px", fontsize=9)
        rgb_axes.axis("off")
        depth = np.ma.masked_equal(frames[index]["depth"], 0.0)  # 0 = no depth
        depth_axes = figure.add_subplot(grid[1, column])
        depth_axes.imshow(depth, cmap="viridis")
        depth_axes.axis("off")
    steps = np.arange(len(frames))
    curve = figure.add_subplot(grid[2, : max(1, len(shown) // 2)])
    curve.plot(steps, [info["occlusion_pixels"] for info in infos], marker=".", label="occlusion L [px]")
    curve.set_xlabel("step")
    curve.set_ylabel("occlusion L [px]")
    reward_axes = curve.twinx()
    reward_axes.plot(steps[1:], rewards[1:], color="tab:red", marker=".", label="reward")
    reward_axes.set_ylabel("reward", color="tab:red")
    path = figure.add_subplot(grid[2, max(1, len(shown) // 2):])
    azimuth = np.degrees([info["azimuth"] for info in infos])
    elevation = np.degrees([info["elevation"] for info in infos])
    path.plot(azimuth, elevation, marker=".")
    path.plot(azimuth[:1], elevation[:1], "go", label="start")
    path.plot(azimuth[-1:], elevation[-1:], "r*", markersize=12, label="end")
    path.set_xlabel("azimuth [deg]")
    path.set_ylabel("elevation [deg]")
    path.yaxis.set_label_position("right")  # clear of the reward axis on the left
    path.yaxis.tick_right()
    path.legend(fontsize=8)
    outcome = "solved" if solved else "not solved"
    figure.suptitle(f"{title}: {outcome} after {len(frames) - 1} steps "
                    "(rows: RGB, depth with no depth blank)")
    figure.tight_layout()
    figure.savefig(out, dpi=90)
    print(f"wrote {out}: {len(frames) - 1} steps, {outcome}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--agent", default="predicted_escape")
    parser.add_argument("--seed", type=int, default=1, help="the scene's seed")
    parser.add_argument("--size", type=int, default=128, help="image width and height [px]")
    parser.add_argument("--max-steps", type=int, default=50)
    parser.add_argument("--frames", type=int, default=5, help="steps shown as images")
    parser.add_argument("--out", default="episode.png")
    args = parser.parse_args()
    frames, infos, rewards, solved = run_episode(args.agent, args.seed, args.size, args.max_steps)
    plot(frames, infos, rewards, solved, args.frames, f"{args.agent}, scene seed {args.seed}",
         args.out)


if __name__ == "__main__":
    main()
