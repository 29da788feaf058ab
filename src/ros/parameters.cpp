#include "occlusion_env/ros/parameters.hpp"

#include <xmlrpcpp/XmlRpcValue.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/ros/names.hpp"

namespace occlusion_env {
namespace {

std::string typeName(const XmlRpc::XmlRpcValue& value) {
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return "a boolean";
    case XmlRpc::XmlRpcValue::TypeInt:
      return "an integer";
    case XmlRpc::XmlRpcValue::TypeDouble:
      return "a number";
    case XmlRpc::XmlRpcValue::TypeString:
      return "a string";
    case XmlRpc::XmlRpcValue::TypeArray:
      return "a list";
    case XmlRpc::XmlRpcValue::TypeStruct:
      return "a dictionary";
    default:
      return "another type";
  }
}

[[noreturn]] void throwWrongType(const ros::NodeHandle& node, const std::string& name,
                                 const std::string& expected, const XmlRpc::XmlRpcValue& value) {
  std::ostringstream message;
  message << "parameter " << node.resolveName(name) << " must be " << expected << ", got "
          << typeName(value);
  throw ParameterError(message.str());
}

}  // namespace

ParameterReader::ParameterReader(const ros::NodeHandle& node) : node_(node) {}

bool ParameterReader::get(const std::string& name, XmlRpc::XmlRpcValue& value) const {
  return node_.hasParam(name) && node_.getParam(name, value);
}

std::string ParameterReader::prefix(const std::string& name) const {
  return "parameter " + node_.resolveName(name);
}

void ParameterReader::read(const std::string& name, bool& out) const {
  XmlRpc::XmlRpcValue value;
  if (!get(name, value)) return;
  if (value.getType() != XmlRpc::XmlRpcValue::TypeBoolean) {
    throwWrongType(node_, name, "true or false", value);
  }
  out = static_cast<bool>(value);
}

void ParameterReader::read(const std::string& name, double& out) const {
  XmlRpc::XmlRpcValue value;
  if (!get(name, value)) return;
  if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
    out = static_cast<double>(value);
  } else if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) {
    out = static_cast<int>(value);
  } else {
    throwWrongType(node_, name, "a number", value);
  }
  if (!std::isfinite(out)) throwWrongType(node_, name, "a finite number", value);
}

void ParameterReader::read(const std::string& name, std::int64_t& out) const {
  XmlRpc::XmlRpcValue value;
  if (!get(name, value)) return;
  out = integerValue(name, value);
}

std::int64_t ParameterReader::integerValue(const std::string& name,
                                           XmlRpc::XmlRpcValue& value) const {
  // XML-RPC integers are 32-bit; larger values arrive as doubles, accepted when integral.
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(value);
  if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble &&
      std::trunc(static_cast<double>(value)) == static_cast<double>(value) &&
      std::abs(static_cast<double>(value)) < 9.0e15) {
    return static_cast<std::int64_t>(static_cast<double>(value));
  }
  throwWrongType(node_, name, "an integer", value);
}

void ParameterReader::read(const std::string& name, int& out) const {
  std::int64_t wide = out;
  read(name, wide);
  if (wide < std::numeric_limits<int>::min() || wide > std::numeric_limits<int>::max()) {
    throw ParameterError(prefix(name) + " is out of range");
  }
  out = static_cast<int>(wide);
}

void ParameterReader::read(const std::string& name, std::size_t& out) const {
  std::int64_t wide = static_cast<std::int64_t>(out);
  read(name, wide);
  if (wide < 0) throw ParameterError(prefix(name) + " must be >= 0");
  out = static_cast<std::size_t>(wide);
}

void ParameterReader::read(const std::string& name, std::string& out) const {
  XmlRpc::XmlRpcValue value;
  if (!get(name, value)) return;
  if (value.getType() != XmlRpc::XmlRpcValue::TypeString) {
    throwWrongType(node_, name, "a string", value);
  }
  out = static_cast<std::string>(value);
}

void ParameterReader::read(const std::string& name, std::vector<std::string>& out) const {
  XmlRpc::XmlRpcValue value;
  if (!get(name, value)) return;
  if (value.getType() != XmlRpc::XmlRpcValue::TypeArray) {
    throwWrongType(node_, name, "a list of strings", value);
  }
  std::vector<std::string> strings;
  for (int i = 0; i < value.size(); ++i) {
    if (value[i].getType() != XmlRpc::XmlRpcValue::TypeString) {
      throwWrongType(node_, name, "a list of strings", value[i]);
    }
    strings.push_back(static_cast<std::string>(value[i]));
  }
  out = std::move(strings);
}

void ParameterReader::read(const std::string& name, std::vector<std::uint64_t>& out) const {
  XmlRpc::XmlRpcValue value;
  if (!get(name, value)) return;
  if (value.getType() != XmlRpc::XmlRpcValue::TypeArray) {
    throwWrongType(node_, name, "a list of integers", value);
  }
  std::vector<std::uint64_t> integers;
  for (int i = 0; i < value.size(); ++i) {
    const std::int64_t integer = integerValue(name, value[i]);
    if (integer < 0) throw ParameterError(prefix(name) + ": values must be >= 0");
    integers.push_back(static_cast<std::uint64_t>(integer));
  }
  out = std::move(integers);
}

nlohmann::json parameterJson(const std::string& name, const XmlRpc::XmlRpcValue& value) {
  XmlRpc::XmlRpcValue& mutable_value = const_cast<XmlRpc::XmlRpcValue&>(value);  // read only
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return static_cast<bool>(mutable_value);
    case XmlRpc::XmlRpcValue::TypeInt:
      return static_cast<int>(mutable_value);
    case XmlRpc::XmlRpcValue::TypeDouble:
      return static_cast<double>(mutable_value);  // NaN and inf are refused by the table
    case XmlRpc::XmlRpcValue::TypeString:
      return static_cast<std::string>(mutable_value);
    case XmlRpc::XmlRpcValue::TypeArray: {
      nlohmann::json list = nlohmann::json::array();
      for (int i = 0; i < value.size(); ++i) list.push_back(parameterJson(name, mutable_value[i]));
      return list;
    }
    default:
      throw ParameterError("parameter " + name + " must not be " + typeName(value));
  }
}

const OptionTable<SimulatorOptions>& simulatorOptionTable() {
  using Options = SimulatorOptions;
  static const auto table =
      OptionTable<Options>()
          .include(environmentOptionTable(),
                   [](Options& o) -> EnvironmentOptions& { return o.environment; })
          .add("world_frame", &Options::world_frame, OptionSpec("fixed frame of the scene"))
          .add("camera_frame", &Options::camera_frame,
               OptionSpec("camera body frame (x forward, z up)"))
          .add("optical_frame", &Options::optical_frame,
               OptionSpec("camera optical frame (z forward); the images' frame_id"))
          .add("tf_rate", &Options::tf_rate_hz,
               OptionSpec("re-broadcast of the camera transform; 0 = only on reset and step")
                   .unit("Hz")
                   .range(0, 1000))
          .add("start_seed", &Options::start_seed,
               OptionSpec("reset with this seed at start-up; -1: wait for a reset").atLeast(-1))
          .add("offer_gradient", &Options::offer_gradient,
               OptionSpec("offer get_occlusion_gradient (false: as a real camera)"))
          .add("mode", &Options::mode,
               OptionSpec("simulator, or camera: stand in for a real camera on a robot")
                   .choices({"simulator", "camera"}))
          .add("camera_rate", &Options::camera_rate_hz,
               OptionSpec("camera mode: frames per second").unit("Hz").above(0).atMost(1000))
          .add("motion_time", &Options::motion_time_s,
               OptionSpec("camera mode: a goal is reached this long after it came")
                   .unit("s")
                   .range(0, 60))
          .add("depth_encoding", &Options::depth_encoding,
               OptionSpec("camera mode: 32FC1 [m] or 16UC1 [mm] (REP 118)")
                   .choices({"32FC1", "16UC1"}));
  return table;
}

std::vector<std::string> simulatorParameterNames() {
  return simulatorOptionTable().keys();
}

SimulatorOptions readSimulatorOptions(const ros::NodeHandle& private_node) {
  SimulatorOptions options;
  readParameters(private_node, simulatorOptionTable(), options);
  try {
    options.environment.validate();  // the rules between options; messages name them
  } catch (const InvalidArgumentError& error) {
    throw ParameterError("invalid parameter in " + private_node.getNamespace() + ": " +
                         error.what());
  }
  for (const std::string* frame :
       {&options.world_frame, &options.camera_frame, &options.optical_frame}) {
    if (frame->empty()) {
      throw ParameterError("parameter " + private_node.getNamespace() +
                           "/*_frame: frame names must not be empty");
    }
  }
  return options;
}

std::vector<std::string> unknownParameters(const ros::NodeHandle& private_node) {
  return unknownParameters(private_node, simulatorParameterNames());
}

std::vector<std::string> unknownParameters(const ros::NodeHandle& private_node,
                                           const std::vector<std::string>& known) {
  std::vector<std::string> all_names;
  if (!private_node.getParamNames(all_names)) return {};
  const std::string prefix = private_node.getNamespace() + "/";
  std::vector<std::string> unknown;
  for (const std::string& full_name : all_names) {
    if (full_name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string name = full_name.substr(prefix.size());
    // A list or dictionary parameter shows up with its sub-keys; compare the first segment.
    const std::string head = name.substr(0, name.find('/'));
    if (std::find(known.begin(), known.end(), head) == known.end()) unknown.push_back(name);
  }
  return unknown;
}

}  // namespace occlusion_env
