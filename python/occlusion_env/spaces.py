"""The observation and action spaces of every occlusion_env environment.

observation_space: Dict with
  rgb    Box(0, 255, (H, W, 3), uint8)            colour, RGB order
  depth  Box(0, MAX_DEPTH_M, (H, W), float32)     metres along the optical axis; 0 = no depth
                                                  (nothing hit, or no valid reading)
  pose   Box([-pi, -e], [pi, e], (2,), float32)   the camera's azimuth and elevation [rad] on
                                                  its sphere, e = the elevation limit
action_space: Box(-1, 1, (2,), float32)           (d_azimuth, d_elevation) in units of step_size
"""

import math

import numpy as np

from occlusion_env import _gym
from occlusion_env._core import MAX_DEPTH_M

DEFAULT_ELEVATION_LIMIT = 1.3962634016  # [rad], 80 deg, sim.yaml's elevation_limit


def observation_space(width, height, elevation_limit=DEFAULT_ELEVATION_LIMIT):
    """The Dict space of observations of width x height images."""
    pose_bound = np.array([math.pi, elevation_limit], dtype=np.float32)
    return _gym.DictSpace(
        {
            "depth": _gym.BoxSpace(
                low=np.zeros((height, width), np.float32),
                high=np.full((height, width), MAX_DEPTH_M, np.float32),
                dtype=np.float32,
            ),
            "pose": _gym.BoxSpace(low=-pose_bound, high=pose_bound, dtype=np.float32),
            "rgb": _gym.BoxSpace(
                low=np.zeros((height, width, 3), np.uint8),
                high=np.full((height, width, 3), 255, np.uint8),
                dtype=np.uint8,
            ),
        }
    )


def action_space():
    """Box(-1, 1, (2,), float32): a move of (d_azimuth, d_elevation) * step_size [rad]."""
    return _gym.BoxSpace(
        low=-np.ones(2, np.float32), high=np.ones(2, np.float32), dtype=np.float32
    )


def checked_action(action):
    """`action` as a float64 array of shape (2,); raises InvalidArgumentError (a ValueError) for
    another shape or a non-finite value."""
    from occlusion_env._core import InvalidArgumentError

    try:
        values = np.asarray(action, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise InvalidArgumentError(f"the action must be 2 numbers: {error}") from None
    if values.shape != (2,):
        raise InvalidArgumentError(f"the action must have shape (2,), got {values.shape}")
    if not np.all(np.isfinite(values)):
        raise InvalidArgumentError(f"the action must be finite, got {values.tolist()}")
    return values
