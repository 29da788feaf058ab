// What the networks see, written down once: an RGB-D observation resized to the network's
// resolution and normalised, as a 4 x S x S float tensor.
//
//   channels 0-2: RGB / 255, then (x - 0.5) / 0.25
//   channel 3:    depth [m] clamped to [0, kFarDepthM] / kFarDepthM, NaN (nothing hit) = 1 (far),
//                 then (x - 0.5) / 0.25
// Resizing: area averaging (cv::INTER_AREA) after the NaNs are replaced, so a pixel at an
// object's edge blends object and far background, as a real depth camera's does.
#pragma once

#include <opencv2/core.hpp>

namespace occlusion_env {
namespace learning {

constexpr double kFarDepthM = 8.0;  // beyond the sphere (r = 4 m) and every object

/// Writes the normalised input of `rgb` (CV_8UC3) and `depth` (CV_32FC1 [m], NaN = nothing) at
/// `size` x `size` into `out` (4 * size * size floats, channel-major). `scratch` holds the
/// resized images between calls (no allocation once sized). Throws InvalidArgumentError on wrong
/// types or sizes.
struct InputScratch {
  cv::Mat depth_filled, rgb_small, depth_small;
};
void writeNetworkInput(const cv::Mat& rgb, const cv::Mat& depth, int size, InputScratch& scratch,
                       float* out);

}  // namespace learning
}  // namespace occlusion_env
