#include "observation_views.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "occlusion_env/common/errors.hpp"

namespace py = pybind11;

namespace occlusion_env {
namespace python {

py::array readOnlyView(const cv::Mat& image) {
  if (!image.isContinuous() || (image.type() != CV_8UC3 && image.type() != CV_32FC1)) {
    throw InvalidArgumentError("readOnlyView: needs a continuous CV_8UC3 or CV_32FC1 image");
  }
  // The capsule owns a header of the image: its reference keeps the pixels alive.
  auto* owner = new cv::Mat(image);
  py::capsule base(owner, [](void* mat) { delete static_cast<cv::Mat*>(mat); });
  py::array view;
  if (image.type() == CV_8UC3) {
    view = py::array_t<std::uint8_t>({image.rows, image.cols, 3}, image.ptr<std::uint8_t>(), base);
  } else {
    view = py::array_t<float>({image.rows, image.cols}, image.ptr<float>(), base);
  }
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

void encodeDepthForPython(const cv::Mat& depth_m, float* out, const cv::Rect& region) {
  const int width = depth_m.cols;
  for (int row = region.y; row < region.y + region.height; ++row) {
    const float* in = depth_m.ptr<float>(row);
    float* to = out + static_cast<std::size_t>(row) * width;
    for (int col = region.x; col < region.x + region.width; ++col) {
      const float d = in[col];
      to[col] = (d > 0.0f && d <= kMaxDepthM) ? d : 0.0f;  // false for NaN
    }
  }
}

cv::Mat rgbFromNumpy(const py::array& rgb) {
  if (rgb.ndim() != 3 || rgb.shape(2) != 3 || !py::isinstance<py::array_t<std::uint8_t>>(rgb)) {
    throw InvalidArgumentError("rgb must be an H x W x 3 uint8 array");
  }
  if (!(rgb.flags() & py::array::c_style)) {
    throw InvalidArgumentError("rgb must be C-contiguous (np.ascontiguousarray)");
  }
  return cv::Mat(static_cast<int>(rgb.shape(0)), static_cast<int>(rgb.shape(1)), CV_8UC3,
                 const_cast<void*>(rgb.data()));
}

void depthFromNumpy(const py::array& depth, cv::Mat& out) {
  auto values = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(depth);
  if (!values || values.ndim() != 2) throw InvalidArgumentError("depth must be an H x W array");
  const int rows = static_cast<int>(values.shape(0)), cols = static_cast<int>(values.shape(1));
  out.create(rows, cols, CV_32FC1);
  const float* in = values.data();
  float* to = out.ptr<float>();
  for (std::size_t i = 0; i < static_cast<std::size_t>(rows) * cols; ++i) {
    to[i] = in[i] > 0.0f ? in[i] : std::numeric_limits<float>::quiet_NaN();
  }
}

Action actionFromPython(const py::handle& action, double step_size_rad) {
  py::array_t<double, py::array::forcecast> values;
  try {
    values = py::array_t<double, py::array::forcecast>::ensure(action);
  } catch (const py::error_already_set&) {
  }
  if (!values) {
    PyErr_Clear();
    throw InvalidArgumentError("the action must be 2 numbers, got " +
                               std::string(py::str(py::type::of(action).attr("__name__"))));
  }
  if (values.ndim() != 1 || values.shape(0) != 2) {
    throw InvalidArgumentError("the action must have shape (2,), got " +
                               std::string(py::str(values.attr("shape"))));
  }
  const double d_azimuth = values.at(0), d_elevation = values.at(1);
  if (!std::isfinite(d_azimuth) || !std::isfinite(d_elevation)) {
    throw InvalidArgumentError("the action must be finite, got (" + std::to_string(d_azimuth) +
                               ", " + std::to_string(d_elevation) + ")");
  }
  return {d_azimuth * step_size_rad, d_elevation * step_size_rad};
}

}  // namespace python
}  // namespace occlusion_env
