// Pictures of the environment's buffers, for people: colourised depth, instance colours and the
// occlusion overlay. Not used on the step path.
#pragma once

#include <opencv2/core.hpp>

namespace occlusion_env {

/// Depth (CV_32FC1 [m], NaN = nothing) as a CV_8UC3 RGB image: near is warm, far is cool,
/// nothing is black. The range is the image's own finite minimum and maximum.
cv::Mat colorizeDepth(const cv::Mat& depth);

/// Instance mask (CV_8UC1, 0 = background) as CV_8UC3 RGB with one fixed colour per object.
cv::Mat colorizeInstances(const cv::Mat& instance);

/// The RGB image dimmed, each object's amodal outline drawn in its instance colour and the
/// occluded pixels (mask != 0) tinted red. `amodal_bits` is CV_8UC1, bit k = object k.
cv::Mat occlusionOverlay(const cv::Mat& rgb, const cv::Mat& amodal_bits, const cv::Mat& mask,
                         int num_objects);

}  // namespace occlusion_env
