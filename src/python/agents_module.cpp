// occlusion_env._agents: the agent registry with the learned agents (libtorch) for Python, kept
// apart from _core so that `import occlusion_env` does not load libtorch; only
// occlusion_env.agents imports this module.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <string>

#include "observation_views.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "python_environment.hpp"

namespace py = pybind11;
using namespace occlusion_env;
using namespace occlusion_env::python;

namespace {

/// The environment of an agent made without one: agents that act on the observations they are
/// given (learned, random) never call it.
class ObservationsOnly : public EnvironmentInterface {
 public:
  StepResult reset(std::uint64_t, const ResetOptions&) override { throw refusal(); }
  StepResult step(const Action&) override { throw refusal(); }
  std::string describe() const override { return "observations given by Python"; }

 private:
  static InvalidStateError refusal() {
    return InvalidStateError("an agent made without env= cannot reset or step an environment");
  }
};

const AgentRegistry& registry() {
  static const AgentRegistry agents = learning::learningAgents();
  return agents;
}

/// An agent called with observations in Python's encoding; answers actions in [-1, 1] units of
/// step_size that the environment turns into the very move the agent chose. Python's observation
/// holds the images and the pose: the agent's RigObservation gets the last action and the step
/// index counted here since reset(); the camera's intrinsics and frame from the environment it
/// was made with (env=) when the images are that environment's size, else none (fx = fy = 0,
/// identity).
class PythonAgent {
 public:
  PythonAgent(const std::string& name, const std::string& model_path, py::object environment,
              double step_size_rad, bool normalize_action)
      : environment_owner_(std::move(environment)),
        step_size_rad_(step_size_rad),
        normalize_action_(normalize_action) {
    EnvironmentInterface* target = nullptr;
    if (environment_owner_.is_none()) {
      detached_ = std::make_unique<ObservationsOnly>();
      target = detached_.get();
    } else {
      Environment& environment = environment_owner_.cast<PythonEnvironment&>().environment();
      attached_ = &environment;
      target = &environment;
    }
    agent_ = registry().make(name, AgentContext{*target, model_path});
  }

  void reset(std::uint64_t seed) {
    agent_->reset(seed);
    info_.last_action = Action{};
    info_.step_index = 0;
  }

  py::array_t<float> act(const py::dict& observation) {
    for (const char* key : {"rgb", "depth", "pose"}) {
      if (!observation.contains(key)) {
        throw InvalidArgumentError(std::string("the observation has no '") + key + "'");
      }
    }
    observation_.rgb = rgbFromNumpy(observation["rgb"].cast<py::array>());
    depthFromNumpy(observation["depth"].cast<py::array>(), depth_);
    observation_.depth = depth_;
    const auto pose = py::array_t<double, py::array::forcecast>::ensure(observation["pose"]);
    if (!pose || pose.size() != 2) throw InvalidArgumentError("pose must hold 2 numbers");
    info_.pose = {pose.at(0), pose.at(1)};
    info_.intrinsics = {observation_.rgb.cols, observation_.rgb.rows, 0.0, 0.0, 0.0, 0.0};
    info_.world_from_optical = Eigen::Isometry3d::Identity();
    if (attached_ != nullptr) {
      // The environment's current view: what a camera's driver and the rig's tf would give.
      const StepInfo& now = attached_->info();
      if (now.intrinsics.width == observation_.rgb.cols &&
          now.intrinsics.height == observation_.rgb.rows) {
        info_.intrinsics = now.intrinsics;
        info_.world_from_optical = now.world_from_optical;
      }
    }
    Action move;
    {
      py::gil_scoped_release release;
      const Action action = agent_->act(rigObservationOf(observation_, info_));
      move = cameraMoveFor(action, step_size_rad_, normalize_action_);
      info_.last_action = action;
      ++info_.step_index;
    }
    py::array_t<float> action(2);
    action.mutable_at(0) = static_cast<float>(move.d_azimuth_rad / step_size_rad_);
    action.mutable_at(1) = static_cast<float>(move.d_elevation_rad / step_size_rad_);
    return action;
  }

 private:
  py::object environment_owner_;  // keeps the environment of a reference agent alive
  std::unique_ptr<EnvironmentInterface> detached_;
  const Environment* attached_ = nullptr;  // the environment of a reference agent, or none
  std::unique_ptr<Agent> agent_;
  double step_size_rad_;
  bool normalize_action_;
  Observation observation_;  // rgb and depth only
  StepInfo info_;            // what the agent is told besides the images
  cv::Mat depth_;            // the core's encoding of the last depth (NaN = nothing hit)
};

py::list entries() {
  py::list list;
  for (const AgentEntry& entry : registry().entries()) {
    py::dict item;
    item["name"] = entry.name;
    item["summary"] = entry.summary;
    item["needs_simulator"] = entry.needs.occlusion_gradient || entry.needs.simulation ||
                              entry.needs.privileged_observation;
    item["needs_model_file"] = entry.needs.model_file;
    item["default_model_path"] = entry.default_model_path;
    item["competes"] = entry.competes;
    list.append(item);
  }
  return list;
}

}  // namespace

PYBIND11_MODULE(_agents, m) {
  m.doc() = "The agents of occlusion_env with the learned ones (use occlusion_env.agents)";
  py::module_::import("occlusion_env._core");  // its exception types and Environment
  m.def("entries", &entries, "Every registered agent: name, summary, needs.");
  py::class_<PythonAgent>(m, "Agent")
      .def(py::init<const std::string&, const std::string&, py::object, double, bool>(),
           py::arg("name"), py::arg("model_path"), py::arg("environment"), py::arg("step_size"),
           py::arg("normalize_action"))
      .def("reset", &PythonAgent::reset, py::arg("seed"))
      .def("act", &PythonAgent::act, py::arg("observation"));
}
