// Observations that hold only the rig's path (no images): for tests of what an agent reads from
// its pose and its own moves.
#pragma once

#include <opencv2/core.hpp>

#include "occlusion_env/env/environment_interface.hpp"

namespace occlusion_env {
namespace testing_support {

/// The rig at (azimuth, elevation) [rad] after the step `step` that asked for `asked`.
inline RigObservation rigAt(double azimuth, double elevation, Action asked, int step) {
  static const cv::Mat no_image;
  RigObservation observation{no_image, no_image};
  observation.pose = {azimuth, elevation};
  observation.last_action = asked;
  observation.step_index = step;
  return observation;
}

}  // namespace testing_support
}  // namespace occlusion_env
