"""The package's agents called from Python."""

import os

import numpy as np
import pytest

import occlusion_env
from occlusion_env import agents

SIZE = dict(width=64, height=64)


def test_registry_lists_the_learned_agents():
    names = agents.names()
    for name in ("random", "gradient", "oracle", "predicted_gradient", "predicted_escape"):
        assert name in names
    with pytest.raises(occlusion_env.InvalidArgumentError, match="agents:"):
        agents.load("no_such_agent")


def test_predicted_escape_acts_on_observations_of_any_source():
    env = occlusion_env.make(**SIZE)
    agent = agents.load("predicted_escape", env=env)
    observation, _ = env.reset(seed=1)
    action = agent(observation)
    assert action in env.action_space
    assert abs(np.hypot(*action.astype(np.float64)) - 1.0) < 1e-5  # a unit move, normalised
    # The same observation as copies (a vector slot, a ROS response) gives the same action.
    copies = {key: np.array(value) for key, value in observation.items()}
    np.testing.assert_array_equal(agents.load("predicted_escape")(copies), action)
    env.step(action)


def test_depth_geometry_needs_the_cameras_intrinsics_and_frame_from_an_env():
    env = occlusion_env.make(**SIZE)
    observation, _ = env.reset(seed=1)
    action = agents.load("depth_geometry", env=env)(observation)
    assert action in env.action_space
    assert abs(np.hypot(*action.astype(np.float64)) - 1.0) < 1e-5
    # Without an env it has neither, and says so rather than guess.
    with pytest.raises(occlusion_env.InvalidArgumentError, match="depth_geometry needs"):
        agents.load("depth_geometry")(observation)


MODELS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "models")


def test_a_model_that_sees_an_angle_of_view_takes_the_envs_intrinsics():
    # The escape network seeing the middle 60 deg of any camera: through the env's own 60 deg
    # camera the very input, so the very action, of the network without the field; without
    # env= it has no intrinsics to find its angle in.
    env = occlusion_env.make(**SIZE)
    fixed_angle = os.path.join(MODELS, "multitask_unet64_escape_fov60.pt")
    plain = os.path.join(MODELS, "multitask_unet64_escape.pt")
    observation, _ = env.reset(seed=1)
    action = agents.load("predicted_escape", env=env, model_path=fixed_angle)(observation)
    np.testing.assert_array_equal(
        action, agents.load("predicted_escape", env=env, model_path=plain)(observation))
    with pytest.raises(occlusion_env.InvalidArgumentError, match="intrinsics"):
        agents.load("predicted_escape", model_path=fixed_angle)(observation)


def test_agents_that_read_the_simulation_need_the_env():
    with pytest.raises(occlusion_env.InvalidArgumentError, match="env="):
        agents.load("oracle")
    env = occlusion_env.make(max_steps=30, **SIZE)
    oracle = agents.load("oracle", env=env)
    observation, info = env.reset(seed=2)
    start = info["occlusion_pixels"]
    done = False
    while not done:
        observation, _, terminated, truncated, info = env.step(oracle(observation))
        done = terminated or truncated
    assert terminated and info["occlusion_pixels"] < start


def test_only_the_agents_module_loads_libtorch():
    import subprocess
    import sys

    script = (
        "import occlusion_env\n"
        "occlusion_env.make(width=64, height=64).reset(seed=1)\n"
        "before = 'libtorch' in open('/proc/self/maps').read()\n"
        "from occlusion_env import agents\n"
        "after = 'libtorch' in open('/proc/self/maps').read()\n"
        "print(before, after)\n")
    output = subprocess.run([sys.executable, "-c", script], check=True, capture_output=True,
                            text=True, timeout=120).stdout.split()
    assert output == ["False", "True"]
