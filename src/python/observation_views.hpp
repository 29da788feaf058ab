// Images between the C++ core and numpy for the Python modules (_core, _agents): read-only views
// where the memory can be shared, and the one encoding of invalid depth Python sees (0).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <opencv2/core.hpp>

#include "occlusion_env/env/environment_interface.hpp"

namespace occlusion_env {
namespace python {

/// Depth Python sees: metres in (0, kMaxDepthM]; 0 where nothing is hit or the reading is not a
/// depth in that range (NaN, +inf, beyond the renderer's far plane). The Box's upper bound.
constexpr float kMaxDepthM = 100.0f;

/// A read-only numpy view of `image` (CV_8UC3 -> H x W x 3 uint8, CV_32FC1 -> H x W float32)
/// that keeps the image's memory alive; it shows whatever is written there later.
pybind11::array readOnlyView(const cv::Mat& image);

/// Writes depth [m] with NaN = nothing hit as Python's depth (0 = nothing hit) into `out`
/// (width * height floats), rows `region` only (the rest is left as it was).
void encodeDepthForPython(const cv::Mat& depth_m, float* out, const cv::Rect& region);

/// An RGB image (H x W x 3 uint8, C-contiguous) as a cv::Mat sharing its memory; throws
/// InvalidArgumentError naming what is wrong.
cv::Mat rgbFromNumpy(const pybind11::array& rgb);

/// Python's depth (H x W float32, 0 = nothing hit) as the core's (NaN = nothing hit) into `out`.
void depthFromNumpy(const pybind11::array& depth, cv::Mat& out);

/// A Python action (anything numpy reads as 2 finite numbers in [-1, 1] units of step_size_rad)
/// as the core's move [rad]. Throws InvalidArgumentError for another shape or a non-finite value.
Action actionFromPython(const pybind11::handle& action, double step_size_rad);

}  // namespace python
}  // namespace occlusion_env
