"""The environment over ROS: the simulator node or the camera bridge of a real camera, through
their reset and step services, with the API of the in-process environment.

Each observation comes in the service's response (the view rendered or captured for that very
reset or step), so it is never stale; rospy is imported only when this environment is made, and
no ROS node is started (service calls need none).
"""


import numpy as np

from occlusion_env import _gym, spaces
from occlusion_env._core import (
    CatalogError,
    EnvironmentUnavailableError,
    InvalidArgumentError,
    InvalidStateError,
    RenderError,
    SceneGenerationError,
)

_RESET_ATTEMPTS = 3  # transport failures of one reset before it gives up (a reset is idempotent)


def _error_for(status):
    """The exception of a refused request (occlusion_env/Status codes)."""
    kinds = {1: InvalidArgumentError, 2: InvalidStateError, 3: CatalogError, 4: RenderError,
             5: SceneGenerationError, 7: EnvironmentUnavailableError}
    return kinds.get(status.code, RuntimeError)(status.message or f"status code {status.code}")


def _image(message, channels, dtype):
    """A sensor_msgs/Image as an array of rows x cols (x channels), a view of its bytes."""
    data = np.frombuffer(message.data, dtype=np.dtype(dtype).newbyteorder(
        ">" if message.is_bigendian else "<"))
    item = np.dtype(dtype).itemsize
    rows = data.reshape(message.height, message.step // item)
    image = rows[:, : message.width * channels]
    return image.reshape(message.height, message.width, channels) if channels > 1 else image


def _depth_for_python(message):
    """Depth [m] with 0 = no depth (NaN, no reading, out of range), as the in-process env."""
    if message.encoding == "16UC1":
        depth = _image(message, 1, np.uint16).astype(np.float32) * np.float32(0.001)
    elif message.encoding == "32FC1":
        depth = _image(message, 1, np.float32).astype(np.float32)
    else:
        raise InvalidArgumentError(f"depth encoding {message.encoding!r} is not 32FC1 or 16UC1")
    valid = (depth > 0) & (depth <= spaces.MAX_DEPTH_M)  # False for NaN
    return np.where(valid, depth, np.float32(0))


class RosOcclusionEnv(_gym.BaseEnv):
    """``RosOcclusionEnv(namespace="/", render_mode=None, copy=False, timeout=60.0, width=None,
    height=None, step_size=None, elevation_limit=None)``.

    Talks to ``<namespace>/occlusion/reset`` and ``.../step``. Image size, step size and
    elevation limit are read from the simulator's parameters (``<namespace>/occlusion_sim/...``)
    or the camera bridge's (``<namespace>/camera_bridge/...``) unless given; behind a camera
    bridge the image size must be given. Observations, spaces, seeding and errors as
    OcclusionEnv's; rgb is a read-only view of the response's bytes (``copy=True`` copies it).
    A service that cannot be reached raises EnvironmentUnavailableError (a ConnectionError).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(self, namespace="/", render_mode=None, copy=False, timeout=60.0, width=None,
                 height=None, step_size=None, elevation_limit=None):
        import rospy
        from occlusion_env.srv import Reset, Step

        if render_mode not in (None, "rgb_array"):
            raise InvalidArgumentError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self.render_mode = render_mode
        self.copy = bool(copy)
        self.namespace = "/" + namespace.strip("/")
        prefix = self.namespace.rstrip("/") + "/occlusion/"
        self._rospy, self._types = rospy, {"reset": Reset, "step": Step}
        self._names = {"reset": prefix + "reset", "step": prefix + "step"}
        for name in self._names.values():
            try:
                rospy.wait_for_service(name, timeout=timeout)
            except rospy.ROSException as error:
                raise EnvironmentUnavailableError(f"{name} not offered within {timeout} s: {error}") from None
        self._proxies = {}
        param = self._parameter_reader()
        width, height = width or param("width"), height or param("height")
        if not width or not height:
            raise InvalidArgumentError("give width and height: no occlusion_sim parameters under "
                                       + self.namespace)
        self.step_size = float(step_size or param("step_size") or 0.05)
        limit = float(elevation_limit or param("elevation_limit") or spaces.DEFAULT_ELEVATION_LIMIT)
        self.options = {"width": int(width), "height": int(height), "step_size": self.step_size,
                        "elevation_limit": limit}
        self.observation_space = spaces.observation_space(int(width), int(height), limit)
        self.action_space = spaces.action_space()
        self._rgb = None
        self._episode_over = False
        self._scene_seed = 0

    def _parameter_reader(self):
        base = self.namespace.rstrip("/")

        def read(name):
            for node in ("occlusion_sim", "camera_bridge"):
                key = f"{base}/{node}/{name}"
                if self._rospy.has_param(key):
                    return self._rospy.get_param(key)
            return None

        return read

    def _call(self, service, request):
        """The response of `service`, or the exception for a refusal or a lost connection."""
        if self._proxies is None:
            raise InvalidStateError("the environment is closed")
        proxy = self._proxies.get(service)
        if proxy is None:
            proxy = self._rospy.ServiceProxy(self._names[service], self._types[service],
                                             persistent=True)
            self._proxies[service] = proxy
        try:
            response = proxy.call(request)
        except (self._rospy.ServiceException, OSError) as error:
            self._proxies.pop(service, None).close()  # reconnect on the next call
            raise EnvironmentUnavailableError(f"{self._names[service]}: {error}") from None
        if response.status.code != 0:
            raise _error_for(response.status)
        return response

    def reset(self, *, seed=None, options=None):
        """As OcclusionEnv.reset; a reset lost in transit is sent again (up to 3 times)."""
        super().reset(seed=seed)
        self._scene_seed = int(seed) if seed is not None else int(self.np_random.integers(2**63))
        request = self._types["reset"]._request_class(seed=self._scene_seed)
        for key, value in dict(options or {}).items():
            if key in ("preset", "object_ids", "categories"):
                setattr(request, key, value)
            elif key in ("start_azimuth", "start_elevation"):
                setattr(request, key, float(value))
                setattr(request, "set_" + key, True)
            else:
                raise InvalidArgumentError(f"unknown reset option {key!r}")
        for attempt in range(_RESET_ATTEMPTS):
            try:
                response = self._call("reset", request)
                break
            except EnvironmentUnavailableError:
                if attempt + 1 == _RESET_ATTEMPTS:
                    raise
        self._episode_over = False
        observation, info = self._read(response.observation)
        info["object_ids"] = list(response.observation.object_ids)
        info["object_categories"] = list(response.observation.object_categories)
        return observation, info

    def step(self, action):
        """As OcclusionEnv.step. A step lost in transit is not sent again (it may have been
        carried out): EnvironmentUnavailableError, and the episode is over."""
        values = spaces.checked_action(action)
        if self._proxies is None:
            raise InvalidStateError("the environment is closed")
        if self._rgb is None:
            raise InvalidStateError("step() before reset(): call reset first")
        if self._episode_over:
            raise InvalidStateError("the episode has ended (terminated or truncated): call reset")
        request = self._types["step"]._request_class()
        request.action.d_azimuth = float(values[0]) * self.step_size
        request.action.d_elevation = float(values[1]) * self.step_size
        try:
            response = self._call("step", request)
        except EnvironmentUnavailableError:
            self._episode_over = True
            raise
        self._episode_over = response.terminated or response.truncated
        observation, info = self._read(response.observation)
        return observation, float(response.reward), bool(response.terminated), bool(
            response.truncated), info

    def _read(self, message):
        height, width = self.observation_space["rgb"].shape[:2]
        if (message.rgb.height, message.rgb.width) != (height, width):
            raise InvalidArgumentError(
                f"the images are {message.rgb.width} x {message.rgb.height}, the environment "
                f"was made for {width} x {height}")
        if message.rgb.encoding != "rgb8":
            raise InvalidArgumentError(f"rgb encoding {message.rgb.encoding!r} is not rgb8")
        rgb = _image(message.rgb, 3, np.uint8)
        self._rgb = rgb
        pose = np.array([message.azimuth, message.elevation], np.float32)
        observation = {"depth": _depth_for_python(message.depth), "pose": pose,
                       "rgb": rgb.copy() if self.copy else rgb}
        info = {"step_index": int(message.step_index),
                "occlusion_pixels": int(message.occlusion.total_pixels),
                "occluded_area_pixels": int(message.occlusion.occluded_area_pixels),
                "union_pixels": int(message.occlusion.union_pixels),
                "azimuth": float(message.azimuth), "elevation": float(message.elevation),
                "scene_seed": self._scene_seed,
                "occlusion_source": ("ground_truth", "estimated", "unavailable")[
                    message.occlusion_source]}
        return observation, info

    def render(self):
        """The current RGB image (a copy) with render_mode "rgb_array"; None without a mode."""
        if self.render_mode is None:
            return None
        if self._rgb is None:
            raise InvalidStateError("render() before reset(): call reset first")
        return self._rgb.copy()

    def close(self):
        """Closes the service connections. Calling it again does nothing."""
        for proxy in (self._proxies or {}).values():
            proxy.close()
        self._proxies = None
        self._rgb = None

