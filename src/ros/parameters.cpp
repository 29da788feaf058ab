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

const std::vector<std::string>& simulatorParameterNames() {
  static const std::vector<std::string> kNames = {"width",
                                                  "height",
                                                  "field_of_view",
                                                  "radius",
                                                  "elevation_limit",
                                                  "start_azimuth_range",
                                                  "start_elevation",
                                                  "catalog_source",
                                                  "catalog_paths",
                                                  "lod_triangle_budget",
                                                  "num_objects",
                                                  "depth_spacing",
                                                  "lateral_sigma",
                                                  "categories",
                                                  "object_ids",
                                                  "preset",
                                                  "max_scene_attempts",
                                                  "normalize_action",
                                                  "step_size",
                                                  "max_steps",
                                                  "reward_normalization",
                                                  "success_bonus",
                                                  "step_penalty",
                                                  "success_threshold",
                                                  "world_frame",
                                                  "camera_frame",
                                                  "optical_frame",
                                                  "tf_rate",
                                                  "start_seed",
                                                  "offer_gradient",
                                                  "gradient_method",
                                                  "gradient_blur_sigma",
                                                  "gradient_finite_difference_step",
                                                  "gradient_zero_tolerance",
                                                  "rasterizer_threads",
                                                  "model_split",
                                                  "mode",
                                                  "camera_rate",
                                                  "motion_time",
                                                  "depth_encoding"};
  return kNames;
}

SimulatorOptions readSimulatorOptions(const ros::NodeHandle& private_node) {
  const ParameterReader reader(private_node);
  SimulatorOptions options;
  options.world_frame = names::kWorldFrame;
  options.camera_frame = names::kCameraFrame;
  options.optical_frame = names::kOpticalFrame;
  EnvironmentOptions& environment = options.environment;

  reader.read("width", environment.width);
  reader.read("height", environment.height);
  reader.read("field_of_view", environment.field_of_view_rad);
  reader.read("radius", environment.radius_m);
  reader.read("elevation_limit", environment.elevation_limit_rad);
  reader.read("start_azimuth_range", environment.start_azimuth_range_rad);
  reader.read("start_elevation", environment.start_elevation_rad);
  reader.read("catalog_source", environment.catalog.source);
  reader.read("catalog_paths", environment.catalog.paths);
  reader.read("lod_triangle_budget", environment.lod_triangle_budget);
  reader.read("num_objects", environment.scene.num_objects);
  reader.read("depth_spacing", environment.scene.depth_spacing_m);
  reader.read("lateral_sigma", environment.scene.lateral_sigma_m);
  reader.read("categories", environment.scene.categories);
  reader.read("object_ids", environment.scene.object_ids);
  reader.read("preset", environment.preset);
  std::string model_split = toString(environment.scene.model_split);
  reader.read("model_split", model_split);
  reader.read("max_scene_attempts", environment.max_scene_attempts);
  reader.read("normalize_action", environment.normalize_action);
  reader.read("step_size", environment.step_size_rad);
  reader.read("max_steps", environment.max_steps);
  std::string normalization = toString(environment.reward.normalization);
  reader.read("reward_normalization", normalization);
  reader.read("success_bonus", environment.reward.success_bonus);
  reader.read("step_penalty", environment.reward.step_penalty);
  reader.read("success_threshold", environment.reward.success_threshold_pixels);
  reader.read("world_frame", options.world_frame);
  reader.read("camera_frame", options.camera_frame);
  reader.read("optical_frame", options.optical_frame);
  reader.read("tf_rate", options.tf_rate_hz);
  reader.read("start_seed", options.start_seed);
  reader.read("offer_gradient", options.offer_gradient);
  reader.read("gradient_method", environment.gradient_method);
  reader.read("gradient_blur_sigma", environment.gradient.blur_sigma_px);
  reader.read("gradient_finite_difference_step", environment.gradient.finite_difference_step_rad);
  reader.read("gradient_zero_tolerance", environment.gradient.zero_gradient_tolerance);
  reader.read("rasterizer_threads", environment.renderer.rasterizer_threads);
  reader.read("mode", options.mode);
  reader.read("camera_rate", options.camera_rate_hz);
  reader.read("motion_time", options.motion_time_s);
  reader.read("depth_encoding", options.depth_encoding);

  const std::string prefix = "parameter " + private_node.getNamespace() + "/";
  try {
    environment.reward.normalization = parseRewardNormalization(normalization);
  } catch (const InvalidArgumentError& error) {
    throw ParameterError(prefix + "reward_normalization: " + error.what());
  }
  try {
    environment.scene.model_split = parseModelSplit(model_split);
  } catch (const InvalidArgumentError& error) {
    throw ParameterError(prefix + "model_split: " + error.what());
  }
  try {
    environment.validate();  // its messages name the option, which is the parameter's name
  } catch (const InvalidArgumentError& error) {
    throw ParameterError("invalid parameter in " + private_node.getNamespace() + ": " +
                         error.what());
  }
  const std::vector<std::string> sources = {"embedded", "sweethome3d", "folder"};
  if (std::find(sources.begin(), sources.end(), environment.catalog.source) == sources.end()) {
    throw ParameterError(prefix + "catalog_source must be embedded, sweethome3d or folder, got '" +
                         environment.catalog.source + "'");
  }
  if (environment.catalog.source == "folder" && environment.catalog.paths.size() != 1) {
    throw ParameterError(prefix +
                         "catalog_paths must hold exactly one root folder when catalog_source "
                         "is folder");
  }
  for (const std::string* frame :
       {&options.world_frame, &options.camera_frame, &options.optical_frame}) {
    if (frame->empty()) throw ParameterError(prefix + "*_frame: frame names must not be empty");
  }
  if (options.tf_rate_hz < 0.0 || options.tf_rate_hz > 1000.0) {
    throw ParameterError(prefix + "tf_rate must be in [0, 1000] Hz");
  }
  if (options.mode != "simulator" && options.mode != "camera") {
    throw ParameterError(prefix + "mode must be simulator or camera, got '" + options.mode + "'");
  }
  if (!(options.camera_rate_hz > 0.0 && options.camera_rate_hz <= 1000.0)) {
    throw ParameterError(prefix + "camera_rate must be in (0, 1000] Hz");
  }
  if (!(options.motion_time_s >= 0.0 && options.motion_time_s <= 60.0)) {
    throw ParameterError(prefix + "motion_time must be in [0, 60] s");
  }
  if (options.depth_encoding != "32FC1" && options.depth_encoding != "16UC1") {
    throw ParameterError(prefix + "depth_encoding must be 32FC1 or 16UC1, got '" +
                         options.depth_encoding + "'");
  }
  if (options.start_seed < -1) {
    throw ParameterError(prefix + "start_seed must be -1 (no reset at start-up) or a seed >= 0");
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
