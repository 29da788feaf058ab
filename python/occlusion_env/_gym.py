"""Gymnasium when it is installed, small stand-ins with the same attributes when it is not.

Gymnasium is imported here, once, when occlusion_env is imported; it is optional. With it, the
environments subclass ``gymnasium.Env`` / ``gymnasium.vector.VectorEnv`` and their spaces are
``gymnasium.spaces`` objects, so Gymnasium's wrappers and ``check_env`` accept them. Without it
(or with ``OCCLUSION_ENV_WITHOUT_GYMNASIUM=1``, for tests), the classes below offer the same
attributes and methods that the environments and their users rely on.
"""

import os

import numpy as np

gymnasium = None
if os.environ.get("OCCLUSION_ENV_WITHOUT_GYMNASIUM", "") != "1":
    try:
        import gymnasium
    except ImportError:
        gymnasium = None


def np_random(seed=None):
    """A numpy Generator seeded as gymnasium.utils.seeding.np_random seeds it, and the seed."""
    if seed is not None and not (isinstance(seed, (int, np.integer)) and seed >= 0):
        raise ValueError(f"seed must be a non-negative int or None, got {seed!r}")
    seed_seq = np.random.SeedSequence(None if seed is None else int(seed))
    generator = np.random.Generator(np.random.PCG64(seed_seq))
    return generator, int(seed_seq.entropy)


class Space:
    """What the environments use of gymnasium.spaces.Space."""

    def __init__(self, shape=None, dtype=None, seed=None):
        self._shape = None if shape is None else tuple(shape)
        self.dtype = None if dtype is None else np.dtype(dtype)
        self._np_random = None
        if seed is not None:
            self.seed(seed)

    @property
    def shape(self):
        return self._shape

    @property
    def np_random(self):
        if self._np_random is None:
            self.seed()
        return self._np_random

    def seed(self, seed=None):
        self._np_random, used = np_random(seed)
        return [used]

    def __contains__(self, x):
        return self.contains(x)


class Box(Space):
    """A box in R^n with bounds low and high (inclusive), like gymnasium.spaces.Box."""

    def __init__(self, low, high, shape=None, dtype=np.float32, seed=None):
        dtype = np.dtype(dtype)
        if shape is None:
            shape = np.shape(low)
        self.low = np.full(shape, low, dtype=dtype)
        self.high = np.full(shape, high, dtype=dtype)
        super().__init__(shape, dtype, seed)

    def contains(self, x):
        if not isinstance(x, np.ndarray):
            try:
                x = np.asarray(x, dtype=self.dtype)
            except (ValueError, TypeError, OverflowError):
                return False
        return bool(
            np.can_cast(x.dtype, self.dtype)
            and x.shape == self.shape
            and np.all(x >= self.low)
            and np.all(x <= self.high)
        )

    def sample(self):
        if np.issubdtype(self.dtype, np.integer):
            values = self.np_random.integers(self.low, self.high, endpoint=True, dtype=self.dtype)
            return np.asarray(values, dtype=self.dtype).reshape(self.shape)
        values = self.np_random.uniform(self.low, self.high, size=self.shape)
        return np.clip(values.astype(self.dtype), self.low, self.high)

    def __eq__(self, other):
        return (
            isinstance(other, Box)
            and self.shape == other.shape
            and self.dtype == other.dtype
            and np.array_equal(self.low, other.low)
            and np.array_equal(self.high, other.high)
        )

    def __repr__(self):
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"


class Dict(Space):
    """Named subspaces, like gymnasium.spaces.Dict (keys sorted as it sorts a plain dict)."""

    def __init__(self, spaces, seed=None):
        self.spaces = dict(sorted(spaces.items()))
        super().__init__(None, None, seed)

    def seed(self, seed=None):
        used = super().seed(seed)
        for space in self.spaces.values():
            space.seed(int(self._np_random.integers(2**31)))
        return used

    def contains(self, x):
        return (
            isinstance(x, dict)
            and x.keys() == self.spaces.keys()
            and all(x[key] in space for key, space in self.spaces.items())
        )

    def sample(self):
        return {key: space.sample() for key, space in self.spaces.items()}

    def __getitem__(self, key):
        return self.spaces[key]

    def __iter__(self):
        return iter(self.spaces)

    def __len__(self):
        return len(self.spaces)

    def keys(self):
        return self.spaces.keys()

    def values(self):
        return self.spaces.values()

    def items(self):
        return self.spaces.items()

    def __eq__(self, other):
        return isinstance(other, Dict) and self.spaces == other.spaces

    def __repr__(self):
        return "Dict(" + ", ".join(f"{k!r}: {s}" for k, s in self.spaces.items()) + ")"


class Env:
    """What occlusion_env uses and offers of gymnasium.Env."""

    metadata = {"render_modes": []}
    render_mode = None
    spec = None
    _np_random = None
    _np_random_seed = None

    def reset(self, *, seed=None, options=None):
        if seed is not None:
            self._np_random, self._np_random_seed = np_random(seed)

    @property
    def np_random(self):
        if self._np_random is None:
            self._np_random, self._np_random_seed = np_random()
        return self._np_random

    @np_random.setter
    def np_random(self, value):
        self._np_random = value
        self._np_random_seed = -1

    @property
    def np_random_seed(self):
        if self._np_random_seed is None:
            self._np_random, self._np_random_seed = np_random()
        return self._np_random_seed

    @property
    def unwrapped(self):
        return self

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *args):
        self.close()
        return False

    def __str__(self):
        return f"<{type(self).__name__} instance>"


class VectorEnv(Env):
    """What occlusion_env uses and offers of gymnasium.vector.VectorEnv."""

    closed = False

    def close(self, **kwargs):
        if self.closed:
            return
        self.close_extras(**kwargs)
        self.closed = True

    def close_extras(self, **kwargs):
        pass


if gymnasium is not None:
    from gymnasium import spaces as _spaces
    from gymnasium.vector import VectorEnv as BaseVectorEnv
    from gymnasium.vector.utils import batch_space

    BaseEnv = gymnasium.Env
    BoxSpace, DictSpace = _spaces.Box, _spaces.Dict
    # AutoresetMode came with Gymnasium 1.1; 1.0 knows only next-step autoreset.
    _modes = getattr(gymnasium.vector, "AutoresetMode", None)
    NEXT_STEP = _modes.NEXT_STEP if _modes is not None else "NextStep"
else:
    BaseEnv, BaseVectorEnv = Env, VectorEnv
    BoxSpace, DictSpace = Box, Dict
    NEXT_STEP = "NextStep"  # the value of gymnasium.vector.AutoresetMode.NEXT_STEP

    def batch_space(space, n):
        """The space of n stacked samples of `space` (Box and Dict of Box)."""
        if isinstance(space, Dict):
            return Dict({key: batch_space(sub, n) for key, sub in space.items()})
        return Box(
            np.stack([space.low] * n), np.stack([space.high] * n), dtype=space.dtype
        )
