// Frames with nothing to occlude, as training frames whose occlusion mask is empty: what keeps a
// network from estimating occlusion where there is none (doc/TRAINING.md, "Known-answer checks").
// Bare surfaces (a floor, a wall, or the corner where they meet: a room without its furniture) and
// one object alone (an object of a dataset frame that nothing hides, everything else the void).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "occlusion_env/env/camera_environment.hpp"

namespace occlusion_env {
namespace learning {

/// A floor, a wall or both, seen by a pinhole camera of `size_px` square pixels (the frame's
/// intrinsics; [16, 4096], else InvalidArgumentError), all drawn from
/// `seed`: horizontal field of view 50-90 deg, camera 0.4-2 m above the floor pitched down by
/// 0-75 deg, the wall 0.7-6 m away and turned by up to +-57 deg, one colour per surface (the floor
/// tiled in a checker pattern in 40 % of the frames), Lambertian shading from one light, pixel
/// noise, and depth noise growing with the square of the distance in half of the frames. Nothing
/// beyond kFarDepthM is seen.
CameraFrame bareSurfaceFrame(std::uint64_t seed, int size_px);

/// `frame` (its rgb and depth; the rest copied) with only the pixels inside `object_mask`
/// (CV_8UC1, non-zero inside) kept and the rest the void (black, no depth). Throws
/// InvalidArgumentError when the sizes differ.
CameraFrame objectAloneFrame(const CameraFrame& frame, const cv::Mat& object_mask);

}  // namespace learning
}  // namespace occlusion_env
