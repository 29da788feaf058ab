// N in-process environments for Python, each on its own thread (VectorEnvironment: a GL context
// belongs to the thread that made it), written straight into batch arrays on those threads.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <string>

#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/env/vector_environment.hpp"

namespace occlusion_env {
namespace python {

class PythonVectorEnvironment {
 public:
  PythonVectorEnvironment(int count, const std::string& options_json);

  /// Environment i resets to seeds[i] where kinds[i] == 1 (with `overrides`), steps by
  /// actions[i] (units of step_size) where kinds[i] == 2, idles where 0; all at once, without the
  /// GIL. Every action of a stepped environment is checked before any environment moves.
  void run(const pybind11::array& kinds, const pybind11::array& seeds,
           const pybind11::handle& actions, const pybind11::dict& overrides);

  /// The batch arrays, rewritten in place by run() for the environments that reset or stepped:
  /// rgb (N, H, W, 3) uint8, depth (N, H, W) float32 (0 = nothing hit), pose (N, 2) float32,
  /// reward float64, terminated and truncated bool, step_index and occlusion_pixels int64,
  /// azimuth and elevation float64 [rad], all (N,).
  pybind11::dict arrays() const { return arrays_; }
  int size() const { return count_; }
  std::string optionsJson() const;

 private:
  void write(int index, const StepResult& result);

  int count_;
  EnvironmentOptions options_;
  pybind11::dict arrays_;
  // Where write() puts environment i's answer (the memory of the arrays in arrays_).
  std::uint8_t* rgb_;
  float *depth_, *pose_;
  double *reward_, *azimuth_, *elevation_;
  bool *terminated_, *truncated_;
  std::int64_t *step_index_, *occlusion_pixels_;
  std::unique_ptr<VectorEnvironment> environments_;
};

}  // namespace python
}  // namespace occlusion_env
