"""The vector environment: Gymnasium's vector contract with NEXT_STEP autoreset."""

import numpy as np
import pytest

import occlusion_env
from occlusion_env import _gym

SIZE = dict(width=64, height=64)


@pytest.fixture(scope="module")
def envs():
    environments = occlusion_env.make_vector(3, max_steps=3, **SIZE)
    yield environments
    environments.close()


def test_spaces_are_batched(envs):
    assert envs.num_envs == 3
    assert envs.metadata["autoreset_mode"] == _gym.NEXT_STEP
    assert envs.observation_space["rgb"].shape == (3, 64, 64, 3)
    assert envs.observation_space["depth"].shape == (3, 64, 64)
    assert envs.observation_space["pose"].shape == (3, 2)
    assert envs.action_space.shape == (3, 2)
    assert envs.single_observation_space["rgb"].shape == (64, 64, 3)
    assert envs.single_action_space.shape == (2,)


def test_reset_matches_single_environments(envs):
    observations, infos = envs.reset(seed=10)
    assert observations in envs.observation_space
    assert list(infos["scene_seed"]) == [10, 11, 12]
    assert infos["_scene_seed"].all()
    for i in range(3):
        single = occlusion_env.make(**SIZE)
        observation, _ = single.reset(seed=10 + i)
        for key in observation:
            np.testing.assert_array_equal(observations[key][i], observation[key], err_msg=key)


def test_next_step_autoreset(envs):
    envs.reset(seed=20)
    single = occlusion_env.make(max_steps=3, **SIZE)
    single.reset(seed=20)
    actions = np.zeros((3, 2), np.float32)
    actions[:, 0] = 1.0
    for step in range(3):
        observations, rewards, terminated, truncated, infos = envs.step(actions)
        single_step = single.step(actions[0])
        assert rewards.shape == (3,) and rewards.dtype == np.float64
        assert terminated.dtype == bool and truncated.dtype == bool
        assert rewards[0] == single_step[1]
        assert terminated[0] == single_step[2] and truncated[0] == single_step[3]
    ended = terminated | truncated
    assert ended.all(), "max_steps 3 ends every episode at the third step"
    # The next step resets: the action is ignored, reward 0, flags False, step index 0.
    observations, rewards, terminated, truncated, infos = envs.step(np.full((3, 2), np.nan))
    assert np.all(rewards == 0) and not terminated.any() and not truncated.any()
    assert np.all(infos["step_index"] == 0)
    # Environment 0's new scene is the one a single environment draws after reset(seed=20).
    observation, info = single.reset()
    assert infos["scene_seed"][0] == info["scene_seed"]
    np.testing.assert_array_equal(observations["rgb"][0], observation["rgb"])
    assert observations in envs.observation_space


def test_bad_actions_and_order(envs):
    fresh = occlusion_env.make_vector(2, **SIZE)
    with pytest.raises(occlusion_env.InvalidStateError):
        fresh.step(np.zeros((2, 2)))
    fresh.reset(seed=1)
    with pytest.raises(occlusion_env.InvalidArgumentError, match="shape"):
        fresh.step(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="finite"):
        fresh.step(np.array([[0.0, 0.0], [np.inf, 0.0]]))
    _, _, _, _, infos = fresh.step(np.zeros((2, 2)))  # the refused step moved nothing
    assert list(infos["step_index"]) == [1, 1]
    fresh.close()
    fresh.close()
    with pytest.raises(occlusion_env.InvalidStateError, match="closed"):
        fresh.reset(seed=1)


def test_copy_and_render():
    envs = occlusion_env.make_vector(2, copy=True, render_mode="rgb_array", **SIZE)
    observations, _ = envs.reset(seed=1)
    kept = observations["rgb"].copy()
    envs.step(np.ones((2, 2)))
    np.testing.assert_array_equal(observations["rgb"], kept)
    frames = envs.render()
    assert len(frames) == 2 and frames[0].shape == (64, 64, 3) and frames[0].dtype == np.uint8
    envs.close()
