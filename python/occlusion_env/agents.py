"""The package's agents, called from Python: ``agents.load("predicted_escape")(obs) -> action``.

The agents come from the C++ agent registry, learned ones included (their libtorch is loaded
when this module is imported, not by ``import occlusion_env``). An agent takes an observation of
any occlusion_env environment (in process, vector slot, over ROS) and answers an action of the
action space, (d_azimuth, d_elevation) in units of step_size, that moves the camera exactly as
the agent decided. Agents that read the simulation (gradient, oracle) need ``env=``, an
in-process OcclusionEnv, and act on its current episode.
"""

from occlusion_env import _agents, spaces
from occlusion_env._core import InvalidArgumentError


def entries():
    """Every agent: a list of dicts with name, summary, needs_simulator (the gradient, the scene
    or the masks and true occlusion: an in-process simulator), needs_model_file,
    default_model_path, competes."""
    return _agents.entries()


def names():
    """The names load() accepts."""
    return [entry["name"] for entry in entries()]


class Agent:
    """A callable agent: ``agent(obs) -> action`` (float32 array of shape (2,))."""

    def __init__(self, name, native, step_size):
        self.name = name
        self.step_size = step_size
        self._native = native

    def reset(self, seed=0):
        """Starts a new episode; `seed` fixes the agent's own random draws (random agent)."""
        self._native.reset(int(seed))

    def __call__(self, observation):
        return self._native.act(observation)

    def __repr__(self):
        return f"<occlusion_env agent {self.name!r}>"


def load(name, model_path="", env=None, step_size=None, normalize_action=None):
    """The agent `name` (see names()). `model_path`: a trained model for the learned agents (""
    = the shipped one). `env`: the environment the actions are for; its step_size and
    normalize_action options apply (else the arguments, else sim.yaml's defaults 0.05 and True).
    An in-process env also gives the agent its camera's intrinsics and frame, which models that
    clear floors and walls, read depth per radius or see a fixed angle of view need.
    """
    entry = next((e for e in entries() if e["name"] == name), None)
    if entry is None:
        raise InvalidArgumentError(f"unknown agent {name!r}; agents: {', '.join(names())}")
    options = getattr(getattr(env, "unwrapped", env), "options", {}) if env is not None else {}
    step_size = float(step_size or options.get("step_size", 0.05))
    normalize = options.get("normalize_action", True) if normalize_action is None else normalize_action
    # An in-process environment: the simulation for the agents that read it, and for every agent
    # the camera's intrinsics and frame of the view it acts on (what a driver and tf would give).
    unwrapped = getattr(env, "unwrapped", env)
    simulator = getattr(unwrapped, "simulator", None) if unwrapped is not None else None
    if entry["needs_simulator"] and simulator is None:
        raise InvalidArgumentError(
            f"agent {name!r} reads the simulation: give env=, an in-process OcclusionEnv")
    native = _agents.Agent(name, model_path or "", simulator, step_size, bool(normalize))
    agent = Agent(name, native, step_size)
    agent.action_space = spaces.action_space()
    return agent
