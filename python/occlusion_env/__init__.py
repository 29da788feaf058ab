"""occlusion_env from Python: the simulated active-perception RGB-D camera with Gymnasium 1.x
semantics (doc/PYTHON.md).

    import occlusion_env
    env = occlusion_env.make(width=128)              # in process (the C++ simulator)
    obs, info = env.reset(seed=1)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

    envs = occlusion_env.make_vector(4, width=128)   # 4 simulators on 4 threads, NEXT_STEP autoreset
    ros_env = occlusion_env.make_ros("/")            # the simulator node or a camera bridge over ROS
    from occlusion_env import agents                 # the package's agents (loads libtorch)
    action = agents.load("predicted_escape", env=env)(obs)

With Gymnasium installed the environments are gymnasium.Env / gymnasium.vector.VectorEnv and
are registered as "occlusion_env/Occlusion-v0" (gymnasium.make and gymnasium.make_vec).
"""

from occlusion_env._core import (
    CatalogError,
    EnvironmentUnavailableError,
    InvalidArgumentError,
    InvalidStateError,
    MAX_DEPTH_M,
    RenderError,
    SceneGenerationError,
)
from occlusion_env._gym import NEXT_STEP
from occlusion_env._gym import gymnasium as _gymnasium
from occlusion_env.env import OcclusionEnv, make
from occlusion_env.vector import OcclusionVectorEnv, make_vector


def make_ros(namespace="/", render_mode=None, copy=False, **kwargs):
    """The environment over ROS services under `namespace` (occlusion_env.ros_env)."""
    from occlusion_env.ros_env import RosOcclusionEnv

    return RosOcclusionEnv(namespace, render_mode=render_mode, copy=copy, **kwargs)


ENV_ID = "occlusion_env/Occlusion-v0"
if _gymnasium is not None and ENV_ID not in _gymnasium.registry:
    _gymnasium.register(
        id=ENV_ID,
        entry_point="occlusion_env.env:OcclusionEnv",
        vector_entry_point="occlusion_env.vector:OcclusionVectorEnv",
    )
