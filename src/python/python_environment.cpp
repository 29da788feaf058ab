#include "python_environment.hpp"

#include <nlohmann/json.hpp>

#include "observation_views.hpp"
#include "occlusion_env/common/errors.hpp"

namespace py = pybind11;

namespace occlusion_env {
namespace python {
namespace {

cv::Rect imageRect(const cv::Mat& image) {
  return {0, 0, image.cols, image.rows};
}

std::vector<std::string> stringList(const py::handle& value, const std::string& key) {
  if (py::isinstance<py::str>(value)) {
    throw InvalidArgumentError("reset option '" + key + "' must be a list of strings");
  }
  try {
    return value.cast<std::vector<std::string>>();
  } catch (const py::cast_error&) {
    throw InvalidArgumentError("reset option '" + key + "' must be a list of strings");
  }
}

double number(const py::handle& value, const std::string& key) {
  try {
    return value.cast<double>();
  } catch (const py::cast_error&) {
    throw InvalidArgumentError("reset option '" + key + "' must be a number [rad]");
  }
}

}  // namespace

EnvironmentOptions environmentOptionsFromJson(const std::string& json_text) {
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(json_text);
  } catch (const nlohmann::json::exception& error) {
    throw InvalidArgumentError(std::string("options are not JSON: ") + error.what());
  }
  EnvironmentOptions options;
  environmentOptionTable().applyJson(json, options);
  options.validate();
  // Gymnasium's observation space has one size: the drawn camera may not change it.
  const std::vector<double>& scales = options.camera_randomization.resolution_scale_range;
  if (options.camera_randomization.enabled && (scales[0] != 1.0 || scales[1] != 1.0)) {
    throw InvalidArgumentError(
        "randomize_camera in Python needs resolution_scale_range [1, 1]: the observation space "
        "has one image size");
  }
  return options;
}

ResetOptions resetOptionsFrom(const py::dict& overrides) {
  ResetOptions reset;
  for (const auto& [key_handle, value] : overrides) {
    const std::string key = py::str(key_handle);
    if (key == "preset") {
      if (!py::isinstance<py::str>(value)) {
        throw InvalidArgumentError("reset option 'preset' must be a string");
      }
      reset.preset = value.cast<std::string>();
    } else if (key == "object_ids") {
      reset.object_ids = stringList(value, key);
    } else if (key == "categories") {
      reset.categories = stringList(value, key);
    } else if (key == "start_azimuth") {
      reset.start_azimuth_rad = number(value, key);
    } else if (key == "start_elevation") {
      reset.start_elevation_rad = number(value, key);
    } else {
      throw InvalidArgumentError("unknown reset option " + quoted(key) +
                                 " (preset, object_ids, categories, start_azimuth, "
                                 "start_elevation)");
    }
  }
  return reset;
}

PythonEnvironment::PythonEnvironment(const std::string& options_json)
    : environment_(environmentOptionsFromJson(options_json)) {
  depth_ = cv::Mat::zeros(environment_.options().height, environment_.options().width, CV_32FC1);
  depth_view_ = readOnlyView(depth_);
}

std::string PythonEnvironment::optionsJson() const {
  return environmentOptionTable().toJson(environment_.options()).dump();
}

py::tuple PythonEnvironment::reset(std::uint64_t seed, const py::dict& overrides) {
  const ResetOptions reset_options = resetOptionsFrom(overrides);
  {
    py::gil_scoped_release release;
    environment_.reset(seed, reset_options);
    // A reset renders into the other set of buffers: all of Python's depth is rewritten.
    encodeDepthForPython(environment_.observation().depth, depth_.ptr<float>(), imageRect(depth_));
  }
  last_footprint_ = environment_.renderBuffers().footprint & imageRect(depth_);
  scene_seed_ = seed;
  py::dict info = this->info();
  py::list ids, categories;
  for (const SceneObject& object : environment_.scene().objects) {
    ids.append(object.model->info.id);
    categories.append(object.model->info.category);
  }
  info["object_ids"] = ids;
  info["object_categories"] = categories;
  py::tuple view = observation();
  return py::make_tuple(view[0], view[1], view[2], info);
}

py::tuple PythonEnvironment::step(const py::handle& action) {
  const Action move = actionFromPython(action, environment_.options().step_size_rad);
  StepResult result;
  {
    py::gil_scoped_release release;
    result = environment_.step(move);
    // Outside the last and the new footprint the depth was and is background (0).
    const cv::Rect footprint = environment_.renderBuffers().footprint & imageRect(depth_);
    encodeDepthForPython(result.observation->depth, depth_.ptr<float>(),
                         footprint | last_footprint_);
    last_footprint_ = footprint;
  }
  py::tuple view = observation();
  return py::make_tuple(view[0], view[1], view[2], result.reward, result.terminated,
                        result.truncated, info());
}

py::tuple PythonEnvironment::observation() {
  const cv::Mat& rgb = environment_.observation().rgb;
  if (rgb.data != rgb_view_data_) {  // a reset swaps the buffers behind the observation
    rgb_view_ = readOnlyView(rgb);
    rgb_view_data_ = rgb.data;
  }
  py::array_t<float> pose(2);
  pose.mutable_at(0) = static_cast<float>(environment_.info().pose.azimuth_rad);
  pose.mutable_at(1) = static_cast<float>(environment_.info().pose.elevation_rad);
  return py::make_tuple(rgb_view_, depth_view_, pose);
}

py::dict PythonEnvironment::info() const {
  const StepInfo& info = environment_.info();
  py::dict dict;
  dict["step_index"] = info.step_index;
  dict["occlusion_pixels"] = info.occlusion.total_pixels;
  dict["occluded_area_pixels"] = info.occlusion.occluded_area_pixels;
  dict["union_pixels"] = info.occlusion.union_pixels;
  dict["azimuth"] = info.pose.azimuth_rad;
  dict["elevation"] = info.pose.elevation_rad;
  dict["scene_seed"] = scene_seed_;
  return dict;
}

}  // namespace python
}  // namespace occlusion_env
