"""N in-process simulators stepped together, with Gymnasium's vector semantics.

Each simulator runs on a thread of its own (a GL context belongs to one thread); one step() call
sends every simulator its request and returns when all have answered, writing straight into the
batch arrays. Autoreset mode: NEXT_STEP (Gymnasium's default, ``metadata["autoreset_mode"]``):
the step() after the one where environment i terminated or truncated resets environment i,
ignores its action and returns its first observation with reward 0, terminated and truncated
False.
"""

import json

import numpy as np

from occlusion_env import _core, _gym, spaces
from occlusion_env._core import InvalidArgumentError, InvalidStateError
from occlusion_env.env import options_json

_IDLE, _RESET, _STEP = 0, 1, 2
_INFO_KEYS = ("step_index", "occlusion_pixels", "azimuth", "elevation")


class OcclusionVectorEnv(_gym.BaseVectorEnv):
    """``OcclusionVectorEnv(num_envs=2, render_mode=None, copy=False, **options)``.

    Observations are a Dict of batched arrays (rgb (N, H, W, 3), depth (N, H, W), pose (N, 2)).
    With ``copy=False`` (the default) they are read-only arrays that the next step() or reset()
    rewrites in place; ``copy=True`` returns copies. Rewards, terminations, truncations and info
    are always new arrays. ``reset(seed=s)`` resets environment i with seed s + i (as
    Gymnasium's SyncVectorEnv does), so it shows the scene ``make().reset(seed=s + i)`` shows.
    An exception from one simulator (raised after all have answered) leaves the others stepped;
    step() then raises InvalidStateError until reset().
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10, "autoreset_mode": _gym.NEXT_STEP}

    def __init__(self, num_envs=2, render_mode=None, copy=False, **options):
        if render_mode not in (None, "rgb_array"):
            raise InvalidArgumentError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self.num_envs = int(num_envs)
        self.render_mode = render_mode
        self.copy = bool(copy)
        self._simulators = _core.VectorEnvironment(self.num_envs, options_json(options))
        self.options = json.loads(self._simulators.options_json())
        self.single_observation_space = spaces.observation_space(
            self.options["width"], self.options["height"], self.options["elevation_limit"]
        )
        self.single_action_space = spaces.action_space()
        self.observation_space = _gym.batch_space(self.single_observation_space, self.num_envs)
        self.action_space = _gym.batch_space(self.single_action_space, self.num_envs)
        self._arrays = self._simulators.arrays()
        self._observation = {}
        for key in ("depth", "pose", "rgb"):
            view = self._arrays[key].view()
            view.flags.writeable = False
            self._observation[key] = view
        self._env_generators = [None] * self.num_envs
        self._scene_seeds = np.zeros(self.num_envs, np.uint64)
        self._autoreset = np.zeros(self.num_envs, bool)
        self._has_reset = False

    def reset(self, *, seed=None, options=None):
        """Resets every environment: (observations, infos). `seed`: None, an int (environment i
        gets seed + i) or a list of num_envs ints or Nones. `options` as OcclusionEnv.reset's,
        for all environments."""
        seeds = self._seeds_for(seed)
        super().reset(seed=seed if isinstance(seed, (int, np.integer)) else None)
        for i, env_seed in enumerate(seeds):
            if env_seed is not None or self._env_generators[i] is None:
                self._env_generators[i], _ = _gym.np_random(env_seed)
            self._scene_seeds[i] = env_seed if env_seed is not None else self._draw_scene_seed(i)
        self._run(np.full(self.num_envs, _RESET), dict(options or {}))
        self._autoreset[:] = False
        self._has_reset = True
        return self._observations(), self._infos()

    def step(self, actions):
        """Steps every environment (NEXT_STEP autoreset, see the module's doc): (observations,
        rewards, terminations, truncations, infos)."""
        if not self._has_reset:
            raise InvalidStateError("step() before reset(): call reset first")
        actions = np.asarray(actions, dtype=np.float64)
        if actions.shape != (self.num_envs, 2):
            raise InvalidArgumentError(
                f"the actions must have shape ({self.num_envs}, 2), got {actions.shape}"
            )
        kinds = np.where(self._autoreset, _RESET, _STEP).astype(np.int8)
        if not np.all(np.isfinite(actions[~self._autoreset])):  # resetting ones are ignored
            raise InvalidArgumentError(f"the actions must be finite, got {actions.tolist()}")
        for i in np.flatnonzero(self._autoreset):
            self._scene_seeds[i] = self._draw_scene_seed(i)
        try:
            self._run(kinds, {}, actions)
        except Exception:
            self._has_reset = False  # some simulators moved, some did not: reset first
            raise
        terminated = self._arrays["terminated"].copy()
        truncated = self._arrays["truncated"].copy()
        self._autoreset = terminated | truncated
        return (self._observations(), self._arrays["reward"].copy(), terminated, truncated,
                self._infos())

    def render(self):
        """One RGB image (a copy) per environment with render_mode "rgb_array"; else None."""
        if self.render_mode is None:
            return None
        if not self._has_reset:
            raise InvalidStateError("render() before reset(): call reset first")
        return tuple(image.copy() for image in self._arrays["rgb"])

    def close_extras(self, **kwargs):
        """Stops the simulators' threads and frees them."""
        self._simulators = None

    def _run(self, kinds, overrides, actions=None):
        if self._simulators is None:
            raise InvalidStateError("the environment is closed")
        if actions is None:
            actions = np.zeros((self.num_envs, 2))
        self._simulators.run(kinds, self._scene_seeds, actions, overrides)

    def _seeds_for(self, seed):
        if seed is None:
            return [None] * self.num_envs
        if isinstance(seed, (int, np.integer)):
            return [int(seed) + i for i in range(self.num_envs)]
        seeds = list(seed)
        if len(seeds) != self.num_envs:
            raise InvalidArgumentError(f"give {self.num_envs} seeds, got {len(seeds)}")
        return seeds

    def _draw_scene_seed(self, index):
        return int(self._env_generators[index].integers(2**63))

    def _observations(self):
        if self.copy:
            return {key: value.copy() for key, value in self._observation.items()}
        return dict(self._observation)

    def _infos(self):
        infos = {}
        for key in _INFO_KEYS:
            infos[key] = self._arrays[key].copy()
            infos["_" + key] = np.ones(self.num_envs, bool)
        infos["scene_seed"] = self._scene_seeds.copy()
        infos["_scene_seed"] = np.ones(self.num_envs, bool)
        return infos


def make_vector(num_envs=2, render_mode=None, copy=False, **options):
    """``occlusion_env.make_vector(4, width=128)``: see OcclusionVectorEnv."""
    return OcclusionVectorEnv(num_envs=num_envs, render_mode=render_mode, copy=copy, **options)
