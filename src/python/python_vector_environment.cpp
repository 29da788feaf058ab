#include "python_vector_environment.hpp"

#include <cstring>
#include <vector>

#include "observation_views.hpp"
#include "occlusion_env/common/errors.hpp"
#include "python_environment.hpp"

namespace py = pybind11;

namespace occlusion_env {
namespace python {
namespace {

/// A new zero-filled array of `shape`; `data` receives its memory.
template <class T>
py::array_t<T> zeros(const std::vector<py::ssize_t>& shape, T** data) {
  py::array_t<T> array(shape);
  *data = array.mutable_data();
  std::memset(static_cast<void*>(*data), 0, array.nbytes());
  return array;
}

}  // namespace

PythonVectorEnvironment::PythonVectorEnvironment(int count, const std::string& options_json)
    : count_(count), options_(environmentOptionsFromJson(options_json)) {
  if (count < 1 || count > 256) {
    throw InvalidArgumentError("num_envs must be in [1, 256], got " + std::to_string(count));
  }
  const py::ssize_t n = count, h = options_.height, w = options_.width;
  arrays_["rgb"] = zeros<std::uint8_t>({n, h, w, 3}, &rgb_);
  arrays_["depth"] = zeros<float>({n, h, w}, &depth_);
  arrays_["pose"] = zeros<float>({n, 2}, &pose_);
  arrays_["reward"] = zeros<double>({n}, &reward_);
  arrays_["terminated"] = zeros<bool>({n}, &terminated_);
  arrays_["truncated"] = zeros<bool>({n}, &truncated_);
  arrays_["step_index"] = zeros<std::int64_t>({n}, &step_index_);
  arrays_["occlusion_pixels"] = zeros<std::int64_t>({n}, &occlusion_pixels_);
  arrays_["azimuth"] = zeros<double>({n}, &azimuth_);
  arrays_["elevation"] = zeros<double>({n}, &elevation_);

  // One object library for all: meshes are loaded and simplified once (it is thread-safe).
  auto library =
      std::make_shared<ObjectLibrary>(makeCatalog(options_.catalog), options_.lod_triangle_budget);
  const EnvironmentOptions options = options_;
  py::gil_scoped_release release;
  environments_ = std::make_unique<VectorEnvironment>(
      count,
      [options, library](int) -> std::unique_ptr<EnvironmentInterface> {
        return std::make_unique<Environment>(options, library);
      },
      [this](int index, const StepResult& result) { write(index, result); });
}

std::string PythonVectorEnvironment::optionsJson() const {
  return environmentOptionTable().toJson(options_).dump();
}

void PythonVectorEnvironment::write(int index, const StepResult& result) {
  const Observation& observation = *result.observation;
  const std::size_t pixels = static_cast<std::size_t>(options_.width) * options_.height;
  std::memcpy(rgb_ + 3 * pixels * index, observation.rgb.data, 3 * pixels);
  encodeDepthForPython(observation.depth, depth_ + pixels * index,
                       {0, 0, options_.width, options_.height});
  pose_[2 * index] = static_cast<float>(result.info.pose.azimuth_rad);
  pose_[2 * index + 1] = static_cast<float>(result.info.pose.elevation_rad);
  reward_[index] = result.reward;
  terminated_[index] = result.terminated;
  truncated_[index] = result.truncated;
  step_index_[index] = result.info.step_index;
  occlusion_pixels_[index] = result.info.occlusion.total_pixels;
  azimuth_[index] = result.info.pose.azimuth_rad;
  elevation_[index] = result.info.pose.elevation_rad;
}

void PythonVectorEnvironment::run(const py::array& kinds, const py::array& seeds,
                                  const py::handle& actions, const py::dict& overrides) {
  auto kind = py::array_t<std::int8_t, py::array::forcecast>::ensure(kinds);
  auto seed = py::array_t<std::uint64_t, py::array::forcecast>::ensure(seeds);
  if (!kind || !seed || kind.size() != count_ || seed.size() != count_) {
    throw InvalidArgumentError("run: kinds and seeds must hold num_envs values");
  }
  py::sequence rows = py::reinterpret_borrow<py::object>(actions);
  if (py::len(rows) != static_cast<std::size_t>(count_)) {
    throw InvalidArgumentError("the actions must have shape (" + std::to_string(count_) +
                               ", 2), got " + std::to_string(py::len(rows)) + " rows");
  }
  const ResetOptions reset = resetOptionsFrom(overrides);
  std::vector<VectorRequest> requests(count_);
  for (int i = 0; i < count_; ++i) {
    if (kind.at(i) == 1) {
      requests[i] = VectorRequest::resetTo(seed.at(i), reset);
    } else if (kind.at(i) == 2) {
      requests[i] = VectorRequest::stepBy(actionFromPython(rows[i], options_.step_size_rad));
    }
  }
  py::gil_scoped_release release;
  environments_->run(requests);
}

}  // namespace python
}  // namespace occlusion_env
