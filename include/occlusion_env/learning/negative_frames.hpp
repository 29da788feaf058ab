// Frames with nothing to occlude, as training frames whose occlusion mask is empty: what keeps a
// network from estimating occlusion where there is none (doc/TRAINING.md, "Known-answer checks").
// Bare surfaces (a floor, a wall, or the corner where they meet: a room without its furniture) and
// one object alone (an object of a dataset frame that nothing hides, everything else the void).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

namespace occlusion_env {
namespace learning {

/// An RGB-D frame as a camera gives it (REP 118 depth).
struct RgbdFrame {
  cv::Mat rgb;    // CV_8UC3
  cv::Mat depth;  // CV_32FC1 [m] along the optical axis, NaN where nothing is seen
};

/// A floor, a wall or both, seen by a pinhole camera of `size_px` square pixels, all drawn from
/// `seed`: horizontal field of view 50-90 deg, camera 0.4-2 m above the floor pitched down by
/// 0-75 deg, the wall 0.7-6 m away and turned by up to +-57 deg, one colour per surface (the floor
/// tiled in a checker pattern in 40 % of the frames), Lambertian shading from one light, pixel
/// noise, and depth noise growing with the square of the distance in half of the frames. Nothing
/// beyond kFarDepthM is seen.
RgbdFrame bareSurfaceFrame(std::uint64_t seed, int size_px);

/// `frame` with only the pixels inside `object_mask` (CV_8UC1, non-zero inside) kept and the rest
/// the void (black, no depth). Throws InvalidArgumentError when the sizes differ.
RgbdFrame objectAloneFrame(const RgbdFrame& frame, const cv::Mat& object_mask);

}  // namespace learning
}  // namespace occlusion_env
