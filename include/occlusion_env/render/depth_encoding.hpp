// Depth as 16-bit millimetres, REP 118's 16UC1, written once: the stand-in camera sends it, the
// camera bridge reads it, the bridge's calibration rounds depth as such a camera would. The
// package's own depth is CV_32FC1 metres with NaN where nothing is hit (doc/CONVENTIONS.md).
#pragma once

#include <opencv2/core.hpp>

namespace occlusion_env {

/// Metres (CV_32FC1, NaN = nothing hit) to millimetres (CV_16UC1), rounded; 0 where there is no
/// reading or the depth is below half a millimetre or beyond 65.535 m. `millimetres` is reused.
/// Throws InvalidArgumentError for another type.
void toMillimetreDepth(const cv::Mat& depth_m, cv::Mat& millimetres);

/// Millimetres (CV_16UC1, 0 = no reading) to metres (CV_32FC1, NaN = no reading). `depth_m` is
/// reused. Throws InvalidArgumentError for another type.
void fromMillimetreDepth(const cv::Mat& millimetres, cv::Mat& depth_m);

}  // namespace occlusion_env
