// ROS parameters read through option tables (common/option_table.hpp), and the simulator's
// options (defaults and meanings: config/sim.yaml, doc/USER_GUIDE.md).
#pragma once

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "occlusion_env/Reset.h"
#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/occlusion/occlusion_gradient.hpp"
#include "occlusion_env/ros/names.hpp"

namespace occlusion_env {

/// A parameter is missing its expected type or value; the message names the parameter.
class ParameterError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A parameter's XML-RPC value as JSON (booleans, integers, doubles, strings, lists of them).
/// Throws ParameterError naming `name` for other types (dictionaries, dates, binary).
nlohmann::json parameterJson(const std::string& name, const XmlRpc::XmlRpcValue& value);

/// Reads every option of `table` that is set under `node` into `options`, each checked as the
/// table declares; absent ones keep their values. Throws ParameterError naming the parameter.
template <class Options>
void readParameters(const ros::NodeHandle& node, const OptionTable<Options>& table,
                    Options& options) {
  for (const OptionField<Options>& field : table.fields()) {
    XmlRpc::XmlRpcValue value;
    if (!node.hasParam(field.key) || !node.getParam(field.key, value)) continue;
    const std::string name = node.resolveName(field.key);
    try {
      table.set(options, field.key, parameterJson(name, value));
    } catch (const InvalidArgumentError& error) {
      throw ParameterError("parameter " + name + ": " + error.what());
    }
  }
}

/// Reads typed parameters relative to a NodeHandle. Each read() leaves `out` unchanged when the
/// parameter is not set and throws ParameterError, naming the parameter, on a wrong type.
class ParameterReader {
 public:
  explicit ParameterReader(const ros::NodeHandle& node);

  void read(const std::string& name, bool& out) const;
  void read(const std::string& name, double& out) const;  // finite
  void read(const std::string& name, std::int64_t& out) const;
  void read(const std::string& name, int& out) const;
  void read(const std::string& name, std::size_t& out) const;  // >= 0
  void read(const std::string& name, std::string& out) const;
  void read(const std::string& name, std::vector<std::string>& out) const;
  void read(const std::string& name, std::vector<std::uint64_t>& out) const;  // each >= 0

  /// "parameter <resolved name>", the start of every error message about `name`.
  std::string prefix(const std::string& name) const;

 private:
  bool get(const std::string& name, XmlRpc::XmlRpcValue& value) const;
  std::int64_t integerValue(const std::string& name, XmlRpc::XmlRpcValue& value) const;

  const ros::NodeHandle& node_;
};

/// Everything SimulatorNode needs besides its NodeHandles.
struct SimulatorOptions {
  EnvironmentOptions environment;
  std::string world_frame = names::kWorldFrame;      // fixed frame of the scene
  std::string camera_frame = names::kCameraFrame;    // camera body frame (x forward)
  std::string optical_frame = names::kOpticalFrame;  // optical frame (z forward); images' frame_id
  double tf_rate_hz = 10.0;      // re-broadcast of the camera transform; 0 = only on reset/step
  std::int64_t start_seed = -1;  // >= 0: reset with this seed at start-up; -1: wait for a reset
  bool offer_gradient = true;    // false: no get_occlusion_gradient, as a real camera

  // ~mode camera: the simulator stands in for a real camera on a robot (ros/stand_in_camera.hpp).
  std::string mode = "simulator";        // simulator | camera
  double camera_rate_hz = 30.0;          // camera mode: frames per second, (0, 1000]
  double motion_time_s = 0.05;           // camera mode: a goal is reached this long after it came
  std::string depth_encoding = "32FC1";  // camera mode: 32FC1 [m] | 16UC1 [mm], 0 = no reading
  bool cameraMode() const { return mode == "camera"; }
};

/// With `start_seed` >= 0, calls the node's reset handler (`reset` or `arrangeScene`) with that
/// seed, as at start-up; throws ParameterError naming ~start_seed when it is refused.
template <typename ResetHandler>
void resetAtStartUp(std::int64_t start_seed, ResetHandler&& reset) {
  if (start_seed < 0) return;
  Reset::Request request;
  Reset::Response response;
  request.seed = static_cast<std::uint64_t>(start_seed);
  reset(request, response);
  if (response.status.code != Status::OK) {
    throw ParameterError("the start-up reset with ~start_seed " + std::to_string(start_seed) +
                         " failed: " + response.status.message);
  }
}

/// Reads every option from `private_node` (the node's `~` namespace); absent parameters keep their
/// defaults. Throws ParameterError naming the first parameter of the wrong type or value.
SimulatorOptions readSimulatorOptions(const ros::NodeHandle& private_node);

/// Names (relative to `private_node`) of parameters set there that the simulator does not read:
/// usually typos.
std::vector<std::string> unknownParameters(const ros::NodeHandle& private_node);

/// Names (relative to `private_node`) of parameters set there that are not in `known`.
std::vector<std::string> unknownParameters(const ros::NodeHandle& private_node,
                                           const std::vector<std::string>& known);

/// The simulator node's parameters: every EnvironmentOptions option, then the node's own.
const OptionTable<SimulatorOptions>& simulatorOptionTable();

/// Every parameter name readSimulatorOptions() reads, relative to the private namespace.
std::vector<std::string> simulatorParameterNames();

}  // namespace occlusion_env
