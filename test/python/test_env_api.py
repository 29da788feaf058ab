"""The in-process environment's Gymnasium contract (doc/PYTHON.md), without Gymnasium."""

import math

import numpy as np
import pytest

import occlusion_env
from occlusion_env import spaces

SIZE = dict(width=64, height=64)


@pytest.fixture
def env():
    environment = occlusion_env.make(**SIZE)
    yield environment
    environment.close()


def copied(observation):
    return {key: np.array(value) for key, value in observation.items()}


def assert_same(a, b):
    assert a.keys() == b.keys()
    for key in a:
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)


def test_spaces(env):
    space = env.observation_space
    assert list(space.keys()) == ["depth", "pose", "rgb"]
    assert space["rgb"].shape == (64, 64, 3) and space["rgb"].dtype == np.uint8
    assert space["depth"].shape == (64, 64) and space["depth"].dtype == np.float32
    assert space["depth"].low.min() == 0 and space["depth"].high.max() == occlusion_env.MAX_DEPTH_M
    assert space["pose"].shape == (2,) and space["pose"].dtype == np.float32
    assert np.all(np.isfinite(space["depth"].high)) and np.all(np.isfinite(space["pose"].high))
    action = env.action_space
    assert action.shape == (2,) and action.dtype == np.float32
    assert np.all(action.low == -1) and np.all(action.high == 1)


def test_reset_and_step_types(env):
    result = env.reset(seed=1)
    assert isinstance(result, tuple) and len(result) == 2
    observation, info = result
    assert observation in env.observation_space
    assert isinstance(info, dict) and info["scene_seed"] == 1 and info["step_index"] == 0
    assert len(info["object_ids"]) == 3 and info["occlusion_pixels"] > 0
    result = env.step(np.array([1.0, 0.0], np.float32))
    assert isinstance(result, tuple) and len(result) == 5
    observation, reward, terminated, truncated, info = result
    assert observation in env.observation_space
    assert type(reward) is float and math.isfinite(reward)
    assert type(terminated) is bool and type(truncated) is bool
    assert info["step_index"] == 1


def test_invalid_depth_is_zero_and_valid_depth_positive(env):
    observation, _ = env.reset(seed=2)
    depth = observation["depth"]
    background = observation["rgb"].sum(axis=2) == 0
    assert not np.isnan(depth).any()
    assert (depth == 0).any() and (depth > 0).any()
    assert np.all(depth[depth > 0] <= occlusion_env.MAX_DEPTH_M)
    # Where nothing is hit the colour is the background's too.
    assert np.all(background[depth == 0])


def test_every_observation_of_an_episode_is_in_the_space():
    env = occlusion_env.make(max_steps=20, **SIZE)
    env.action_space.seed(5)
    observation, _ = env.reset(seed=3)
    done = False
    while not done:
        assert observation in env.observation_space
        observation, _, terminated, truncated, _ = env.step(env.action_space.sample())
        done = terminated or truncated
    assert observation in env.observation_space
    env.close()


def test_seed_then_no_seed_is_deterministic():
    def episode_starts(env):
        first, info_first = env.reset(seed=123)
        first = copied(first)
        second, info_second = env.reset()
        return first, info_first, copied(second), info_second

    a = episode_starts(occlusion_env.make(**SIZE))
    b = episode_starts(occlusion_env.make(**SIZE))
    assert_same(a[0], b[0])
    assert_same(a[2], b[2])
    assert a[1] == b[1] and a[3] == b[3]
    assert a[3]["scene_seed"] != 123  # drawn from np_random


def test_step_is_deterministic_given_seed_and_actions():
    def run(env):
        env.reset(seed=7)
        return [copied(env.step(np.array([0.3, -0.8]))[0]) for _ in range(3)]

    for a, b in zip(run(occlusion_env.make(**SIZE)), run(occlusion_env.make(**SIZE))):
        assert_same(a, b)


def test_views_are_read_only_and_valid_until_the_next_step(env):
    observation, _ = env.reset(seed=4)
    kept = copied(observation)
    with pytest.raises(ValueError):
        observation["rgb"][0, 0, 0] = 1
    assert_same(observation, kept)
    env.step([1.0, 0.0])
    changed = not np.array_equal(observation["rgb"], kept["rgb"])
    assert changed, "a view shows the new step's image"


def test_copy_true_gives_own_arrays():
    env = occlusion_env.make(copy=True, **SIZE)
    observation, _ = env.reset(seed=4)
    kept = copied(observation)
    observation["rgb"][0, 0, 0] = 7  # writable, and the environment's own
    env.step([1.0, 0.0])
    np.testing.assert_array_equal(observation["depth"], kept["depth"])


def test_errors_are_python_exceptions(env):
    with pytest.raises(occlusion_env.InvalidStateError, match="reset"):
        env.step([1.0, 0.0])
    env.reset(seed=1)
    for bad in ([1.0], [[1.0, 0.0]], [1.0, 0.0, 0.0], "ab"):
        with pytest.raises(occlusion_env.InvalidArgumentError):
            env.step(bad)
    for bad in ([math.nan, 0.0], [0.0, math.inf]):
        with pytest.raises(ValueError, match="finite"):
            env.step(bad)
    observation, *_ = env.step([0.0, 1.0])  # the refused steps changed nothing
    assert observation in env.observation_space


def test_step_after_the_end_raises():
    env = occlusion_env.make(max_steps=2, **SIZE)
    env.reset(seed=1)
    done = False
    while not done:
        _, _, terminated, truncated, _ = env.step([0.0, 0.0])
        done = terminated or truncated
    with pytest.raises(occlusion_env.InvalidStateError, match="ended"):
        env.step([0.0, 0.0])
    env.reset()
    env.step([0.0, 0.0])


def test_unknown_and_bad_options_are_refused():
    with pytest.raises(occlusion_env.InvalidArgumentError, match="no_such_option"):
        occlusion_env.make(no_such_option=1)
    with pytest.raises(occlusion_env.InvalidArgumentError, match="width"):
        occlusion_env.make(width=8, height=64)
    env = occlusion_env.make(**SIZE)
    with pytest.raises(occlusion_env.InvalidArgumentError, match="bogus"):
        env.reset(seed=1, options={"bogus": 1})
    # The drawn camera may not change the observation space's image size.
    with pytest.raises(occlusion_env.InvalidArgumentError, match="resolution_scale_range"):
        occlusion_env.make(randomize_camera=True, **SIZE)


def test_randomized_camera_and_world_keep_the_space():
    env = occlusion_env.make(randomize_camera=True, resolution_scale_range=[1.0, 1.0],
                             world="random", depth_sensor="random", **SIZE)
    for seed in (1, 2, 3):
        observation, info = env.reset(seed=seed)
        assert env.observation_space.contains(observation)
        observation, *_ = env.step(np.array([0.05, 0.0], dtype=np.float32))
        assert env.observation_space.contains(observation)
    env.close()


def test_reset_options_override_the_scene(env):
    _, info = env.reset(seed=1, options={"start_azimuth": 0.02, "preset": "two_chairs"})
    assert abs(info["azimuth"] - 0.02) < 1e-12 and len(info["object_ids"]) == 2


def test_render_and_close():
    env = occlusion_env.make(render_mode="rgb_array", **SIZE)
    observation, _ = env.reset(seed=1)
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.shape == (64, 64, 3)
    np.testing.assert_array_equal(frame, observation["rgb"])
    env.close()
    env.close()
    with pytest.raises(occlusion_env.InvalidStateError, match="closed"):
        env.reset(seed=1)
    assert occlusion_env.make(**SIZE).render() is None  # no render mode
    with pytest.raises(ValueError):
        occlusion_env.make(render_mode="human", **SIZE)


def test_stand_in_spaces_behave_like_gymnasiums():
    box = spaces.action_space()
    box.seed(3)
    samples = [box.sample() for _ in range(50)]
    assert all(sample in box for sample in samples)
    assert np.array([np.nan, 0], np.float32) not in box
    assert np.array([2, 0], np.float32) not in box
    assert np.zeros(2, np.float64) not in box  # float64 cannot be cast to float32 safely


def test_another_thread_gets_an_exception_not_a_crash(env):
    import threading

    errors = []

    def reset_elsewhere():
        try:
            env.reset(seed=1)
        except occlusion_env.RenderError as error:
            errors.append(error)

    thread = threading.Thread(target=reset_elsewhere)
    thread.start()
    thread.join()
    assert len(errors) == 1 and "thread" in str(errors[0])
    observation, _ = env.reset(seed=1)  # the owning thread carries on
    assert observation in env.observation_space
