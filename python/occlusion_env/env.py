"""The in-process environment: the C++ simulator behind Gymnasium's Env API."""

import json

import numpy as np

from occlusion_env import _core, _gym, spaces
from occlusion_env._core import InvalidArgumentError, InvalidStateError


def options_json(options):
    """Keyword options (sim.yaml names) as the JSON the C++ option table reads; numpy scalars and
    arrays become numbers and lists."""

    def plain(value):
        if isinstance(value, np.generic):
            return value.item()
        if isinstance(value, np.ndarray):
            return value.tolist()
        raise InvalidArgumentError(f"option value {value!r} is not a number, string or list")

    return json.dumps(options, default=plain)


def observation_dict(rgb, depth, pose, copy):
    """The observation in the space's key order; copies of the views when `copy`."""
    if copy:
        return {"depth": depth.copy(), "pose": pose, "rgb": rgb.copy()}
    return {"depth": depth, "pose": pose, "rgb": rgb}


class OcclusionEnv(_gym.BaseEnv):
    """The simulator in this process (C++ Environment), with Gymnasium 1.x semantics.

    ``OcclusionEnv(render_mode=None, copy=False, **options)``; options are the simulator's
    parameters by their sim.yaml names (width=128, catalog_source="sweethome3d", ...): unknown
    names and bad values raise InvalidArgumentError (a ValueError).

    Observations (see occlusion_env.spaces): with ``copy=False`` (the default) ``rgb`` and
    ``depth`` are read-only views of the simulator's buffers, valid until the next step() or
    reset() of this environment, which rewrites them; keep ``obs["rgb"].copy()`` or make the
    environment with ``copy=True``. ``pose`` is always a new array.

    Seeding: ``reset(seed=s)`` seeds ``np_random`` and shows the scene of seed s (the scene the
    C++ tools draw for seed s); ``reset()`` draws the next scene seed from ``np_random``. The
    episode's scene seed is ``info["scene_seed"]``.

    The environment belongs to the thread that made it (its GL context does): calls from another
    thread raise RenderError.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(self, render_mode=None, copy=False, **options):
        if render_mode not in (None, "rgb_array"):
            raise InvalidArgumentError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self.render_mode = render_mode
        self.copy = bool(copy)
        self._simulator = _core.Environment(options_json(options))
        self.options = json.loads(self._simulator.options_json())
        self.observation_space = spaces.observation_space(
            self.options["width"], self.options["height"], self.options["elevation_limit"]
        )
        self.action_space = spaces.action_space()
        self._rgb = None  # the last observation's colour image, for render()
        self._episode_over = False

    def reset(self, *, seed=None, options=None):
        """Starts an episode: (observation, info). `options` overrides the scene of this episode:
        preset, object_ids, categories, start_azimuth, start_elevation [rad]."""
        super().reset(seed=seed)
        simulator = self._open_simulator()
        scene_seed = int(seed) if seed is not None else int(self.np_random.integers(2**63))
        rgb, depth, pose, info = simulator.reset(scene_seed, dict(options or {}))
        self._rgb = rgb
        self._episode_over = False
        return observation_dict(rgb, depth, pose, self.copy), info

    def step(self, action):
        """Moves the camera by action * step_size [rad]: (obs, reward, terminated, truncated,
        info). Raises InvalidStateError before reset() and after the episode's end, and
        InvalidArgumentError for an action that is not 2 finite numbers."""
        simulator = self._open_simulator()
        if self._rgb is None:
            raise InvalidStateError("step() before reset(): call reset first")
        if self._episode_over:
            raise InvalidStateError("the episode has ended (terminated or truncated): call reset")
        rgb, depth, pose, reward, terminated, truncated, info = simulator.step(action)
        self._rgb = rgb
        self._episode_over = terminated or truncated
        return observation_dict(rgb, depth, pose, self.copy), reward, terminated, truncated, info

    def render(self):
        """The current RGB image (a copy) with render_mode "rgb_array"; None without a mode."""
        if self.render_mode is None:
            return None
        self._open_simulator()
        if self._rgb is None:
            raise InvalidStateError("render() before reset(): call reset first")
        return self._rgb.copy()

    def close(self):
        """Frees the simulator (its GL context and buffers). Calling it again does nothing."""
        self._simulator = None
        self._rgb = None

    @property
    def simulator(self):
        """The C++ environment (for occlusion_env.agents' reference agents)."""
        return self._open_simulator()

    def _open_simulator(self):
        if self._simulator is None:
            raise InvalidStateError("the environment is closed")
        return self._simulator


def make(render_mode=None, copy=False, **options):
    """An in-process environment: ``occlusion_env.make(width=128)``; see OcclusionEnv."""
    return OcclusionEnv(render_mode=render_mode, copy=copy, **options)
