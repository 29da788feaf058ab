#!/usr/bin/env python3
"""PPO on occlusion_env's vector environment, in one file (CleanRL's ppo_continuous_action shape:
rollout storage [steps, envs], GAE, minibatches, clipped surrogate). A starting point, not the
package's trainer (occlusion_train_ppo is that).

    source .build_ws/devel/setup.bash
    python3 examples/ppo_vector_env.py --num-envs 4 --updates 200          # ~1 h on 2 cores
    python3 examples/ppo_vector_env.py --updates 2 --num-envs 2 --num-steps 16   # a smoke run

Autoreset is NEXT_STEP (the vector env's, Gymnasium's default): the step after an episode ended
returns the next episode's first observation, ignores the action and gives reward 0. That
transition belongs to no episode, so it is masked out of the loss and cuts GAE; since the
observation returned with truncated=True is the episode's last one, a truncated episode is
bootstrapped from its value.
"""

import argparse
import time

import numpy as np
import torch
import torch.nn as nn

import occlusion_env


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add = parser.add_argument
    add("--seed", type=int, default=1, help="seeds the scenes, the policy and the sampling")
    add("--num-envs", type=int, default=4, help="simulators, one thread each")
    add("--num-steps", type=int, default=64, help="steps per environment per update")
    add("--updates", type=int, default=100, help="policy updates")
    add("--size", type=int, default=64, help="image width and height [px]")
    add("--max-steps", type=int, default=50, help="episode length before truncation")
    add("--learning-rate", type=float, default=3e-4)
    add("--gamma", type=float, default=0.99)
    add("--gae-lambda", type=float, default=0.95)
    add("--num-minibatches", type=int, default=4)
    add("--update-epochs", type=int, default=4)
    add("--clip-coef", type=float, default=0.2)
    add("--ent-coef", type=float, default=0.0)
    add("--vf-coef", type=float, default=0.5)
    add("--max-grad-norm", type=float, default=0.5)
    add("--threads", type=int, default=1, help="torch threads (the simulators use the others)")
    add("--save", default="", help="write the policy's state_dict here at the end")
    return parser.parse_args()


def to_tensor(observations):
    """The batch (N, 4, H, W) images in [0, 1] and (N, 2) poses; depth 0 (no depth) stays 0."""
    rgb = torch.from_numpy(np.array(observations["rgb"])).permute(0, 3, 1, 2).float() / 255.0
    depth = torch.from_numpy(np.array(observations["depth"])).unsqueeze(1) / 10.0
    return torch.cat([rgb, depth.clamp(max=1.0)], dim=1), torch.from_numpy(
        np.array(observations["pose"]))


class Agent(nn.Module):
    """A small convolutional encoder, a Gaussian actor with a learned log std and a critic."""

    def __init__(self, size):
        super().__init__()
        self.encoder = nn.Sequential(
            nn.Conv2d(4, 16, 8, stride=4), nn.ReLU(),
            nn.Conv2d(16, 32, 4, stride=2), nn.ReLU(),
            nn.Flatten())
        features = self.encoder(torch.zeros(1, 4, size, size)).shape[1]
        self.trunk = nn.Sequential(nn.Linear(features + 2, 128), nn.ReLU())
        self.actor_mean = nn.Linear(128, 2)
        self.actor_logstd = nn.Parameter(torch.full((1, 2), -0.5))
        self.critic = nn.Linear(128, 1)

    def forward(self, images, poses, action=None):
        hidden = self.trunk(torch.cat([self.encoder(images), poses], dim=1))
        mean = torch.tanh(self.actor_mean(hidden))
        dist = torch.distributions.Normal(mean, self.actor_logstd.expand_as(mean).exp())
        if action is None:
            action = dist.sample()
        return (action, dist.log_prob(action).sum(1), dist.entropy().sum(1),
                self.critic(hidden).squeeze(1))


def advantages_for(rewards, values, last_value, terminated, ended, valid, gamma, lam):
    """GAE over [steps, envs]; `valid` False marks NEXT_STEP's reset transitions."""
    advantages = torch.zeros_like(rewards)
    last = torch.zeros_like(last_value)
    steps = rewards.shape[0]
    for t in reversed(range(steps)):
        next_value = last_value if t == steps - 1 else values[t + 1]
        delta = rewards[t] + gamma * next_value * (1.0 - terminated[t]) - values[t]
        last = (delta + gamma * lam * (1.0 - ended[t]) * last) * valid[t]
        advantages[t] = last
    return advantages


def main():
    args = parse_args()
    torch.manual_seed(args.seed)
    torch.set_num_threads(args.threads)
    envs = occlusion_env.make_vector(args.num_envs, width=args.size, height=args.size,
                                     max_steps=args.max_steps)
    assert envs.metadata["autoreset_mode"] == occlusion_env.NEXT_STEP
    agent = Agent(args.size)
    optimizer = torch.optim.Adam(agent.parameters(), lr=args.learning_rate, eps=1e-5)
    shape = (args.num_steps, args.num_envs)
    images = torch.zeros(shape + (4, args.size, args.size))
    poses, actions = torch.zeros(shape + (2,)), torch.zeros(shape + (2,))
    logprobs, rewards, values = torch.zeros(shape), torch.zeros(shape), torch.zeros(shape)
    terminated, ended, valid = torch.zeros(shape), torch.zeros(shape), torch.zeros(shape)

    observations, _ = envs.reset(seed=args.seed)
    image, pose = to_tensor(observations)
    resetting = np.zeros(args.num_envs, bool)  # the next step resets these (NEXT_STEP)
    returns, episode_return = [], np.zeros(args.num_envs)
    start = time.time()
    for update in range(1, args.updates + 1):
        for t in range(args.num_steps):
            images[t], poses[t] = image, pose
            valid[t] = torch.from_numpy(~resetting).float()
            with torch.no_grad():
                action, logprobs[t], _, values[t] = agent(image, pose)
            actions[t] = action
            observations, reward, term, trunc, _ = envs.step(action.clamp(-1, 1).numpy())
            rewards[t] = torch.from_numpy(reward).float()
            terminated[t] = torch.from_numpy(term).float()
            ended[t] = torch.from_numpy(term | trunc).float()
            episode_return += reward
            for i in np.flatnonzero(term | trunc):
                returns.append(episode_return[i])
                episode_return[i] = 0.0
            resetting = term | trunc
            image, pose = to_tensor(observations)
        with torch.no_grad():
            last_value = agent(image, pose)[3]
        advantages = advantages_for(rewards, values, last_value, terminated, ended, valid,
                                    args.gamma, args.gae_lambda)
        targets = advantages + values
        losses = train(agent, optimizer, args, images.flatten(0, 1), poses.flatten(0, 1),
                       actions.flatten(0, 1), logprobs.flatten(0, 1), advantages.flatten(),
                       targets.flatten(), valid.flatten())
        steps = update * args.num_steps * args.num_envs
        recent = np.mean(returns[-20:]) if returns else float("nan")
        print(f"update {update}/{args.updates}  steps {steps}  episodes {len(returns)}  "
              f"return(last 20) {recent:.3f}  policy loss {losses[0]:.4f}  "
              f"value loss {losses[1]:.4f}  steps/s {steps / (time.time() - start):.0f}",
              flush=True)
    envs.close()
    if args.save:
        torch.save(agent.state_dict(), args.save)


def train(agent, optimizer, args, images, poses, actions, logprobs, advantages, targets, valid):
    """The clipped-surrogate epochs over minibatches of valid transitions; the last losses."""
    indices = torch.nonzero(valid).squeeze(1)
    batch = len(indices)
    minibatch = max(1, batch // args.num_minibatches)
    policy_loss = value_loss = torch.tensor(0.0)
    for _ in range(args.update_epochs):
        order = indices[torch.randperm(batch)]
        for begin in range(0, batch, minibatch):
            chosen = order[begin:begin + minibatch]
            _, logprob, entropy, value = agent(images[chosen], poses[chosen], actions[chosen])
            ratio = (logprob - logprobs[chosen]).exp()
            advantage = advantages[chosen]
            advantage = (advantage - advantage.mean()) / (advantage.std() + 1e-8)
            policy_loss = torch.max(-advantage * ratio, -advantage * ratio.clamp(
                1 - args.clip_coef, 1 + args.clip_coef)).mean()
            value_loss = 0.5 * ((value - targets[chosen]) ** 2).mean()
            loss = policy_loss - args.ent_coef * entropy.mean() + args.vf_coef * value_loss
            optimizer.zero_grad()
            loss.backward()
            nn.utils.clip_grad_norm_(agent.parameters(), args.max_grad_norm)
            optimizer.step()
    return policy_loss.item(), value_loss.item()


if __name__ == "__main__":
    main()
