"""The ROS-backed environment against a simulator node (started by ros_env_test.sh under
$OCCLUSION_TEST_NAMESPACE at 64 px): the same API and the same episodes as in process."""

import os

import numpy as np
import pytest

import occlusion_env

NAMESPACE = os.environ.get("OCCLUSION_TEST_NAMESPACE")
pytestmark = pytest.mark.skipif(NAMESPACE is None, reason="run by test/python/ros_env_test.sh")


@pytest.fixture(scope="module")
def ros_env():
    environment = occlusion_env.make_ros(NAMESPACE, timeout=60.0)
    yield environment
    environment.close()


def test_spaces_from_the_node_parameters(ros_env):
    assert ros_env.observation_space["rgb"].shape == (64, 64, 3)
    assert ros_env.action_space.shape == (2,)


def test_episode_equals_the_in_process_one(ros_env):
    local = occlusion_env.make(width=64, height=64)
    remote_obs, remote_info = ros_env.reset(seed=5)
    local_obs, local_info = local.reset(seed=5)
    assert remote_obs in ros_env.observation_space
    assert remote_info["object_ids"] == local_info["object_ids"]
    for step in range(4):
        for key in ("rgb", "depth", "pose"):
            np.testing.assert_array_equal(remote_obs[key], local_obs[key], err_msg=key)
        action = np.array([0.8, -0.6], np.float32)
        remote_obs, remote_reward, remote_term, remote_trunc, remote_info = ros_env.step(action)
        local_obs, local_reward, local_term, local_trunc, _ = local.step(action)
        assert type(remote_reward) is float and remote_reward == pytest.approx(local_reward)
        assert (remote_term, remote_trunc) == (local_term, local_trunc)
        assert remote_info["step_index"] == step + 1


def test_seed_then_no_seed_is_deterministic(ros_env):
    first, _ = ros_env.reset(seed=9)
    _, info_a = ros_env.reset()
    ros_env.reset(seed=9)
    _, info_b = ros_env.reset()
    assert info_a["scene_seed"] == info_b["scene_seed"] != 9
    assert first in ros_env.observation_space


def test_errors(ros_env):
    ros_env.reset(seed=1)
    with pytest.raises(occlusion_env.InvalidArgumentError):
        ros_env.step([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="finite"):
        ros_env.step([np.nan, 0.0])
    with pytest.raises(occlusion_env.InvalidArgumentError, match="preset"):
        ros_env.reset(seed=1, options={"preset": "no_such_preset"})


def test_unreachable_namespace_is_a_connection_error():
    with pytest.raises(ConnectionError):
        occlusion_env.make_ros("/nobody_here", timeout=0.5)


def test_close_twice(ros_env):
    other = occlusion_env.make_ros(NAMESPACE, timeout=10.0)
    other.reset(seed=1)
    other.close()
    other.close()
    with pytest.raises(occlusion_env.InvalidStateError):
        other.step([1.0, 0.0])
