// The in-process environment as the Python module _core holds it: the C++ Environment plus the
// depth image in Python's encoding. Shared with _agents, whose reference agents read the scene.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>

#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace python {

/// Options from a JSON object of sim.yaml names (environmentOptionTable()); unknown names, wrong
/// types and values out of range throw InvalidArgumentError naming the option.
EnvironmentOptions environmentOptionsFromJson(const std::string& json_text);

/// Per-reset overrides from Python's reset(options=...): preset, object_ids, categories,
/// start_azimuth, start_elevation [rad]; other keys throw InvalidArgumentError.
ResetOptions resetOptionsFrom(const pybind11::dict& overrides);

class PythonEnvironment {
 public:
  /// Makes the environment (and its GL context) on the calling thread, which must make every call.
  explicit PythonEnvironment(const std::string& options_json);

  /// (rgb, depth, pose, info) of the scene drawn from `seed`.
  pybind11::tuple reset(std::uint64_t seed, const pybind11::dict& overrides);
  /// (rgb, depth, pose, reward, terminated, truncated, info); `action` in units of step_size.
  pybind11::tuple step(const pybind11::handle& action);

  Environment& environment() { return environment_; }
  std::string optionsJson() const;

 private:
  pybind11::tuple observation();
  pybind11::dict info() const;

  Environment environment_;
  cv::Mat depth_;               // Python's depth (0 = nothing hit), what depth_view_ shows
  pybind11::array depth_view_;  // read-only view of depth_
  pybind11::array rgb_view_;    // read-only view of the current RGB buffer
  const void* rgb_view_data_ = nullptr;
  cv::Rect last_footprint_;  // where depth_ may hold non-zero values [px]
  std::uint64_t scene_seed_ = 0;
};

}  // namespace python
}  // namespace occlusion_env
