#include "occlusion_env/env/simulated_camera_rig.hpp"

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/render/depth_encoding.hpp"

namespace occlusion_env {

SimulatedCameraRig::SimulatedCameraRig(Environment& environment, bool millimetre_depth)
    : environment_(environment), millimetre_depth_(millimetre_depth) {}

void SimulatedCameraRig::arrangeScene(std::uint64_t seed, const ResetOptions& overrides) {
  environment_.reset(seed, overrides);  // the scene, and the camera at its start pose
}

Eigen::Isometry3d SimulatedCameraRig::cameraPose() {
  if (!environment_.hasEpisode()) {
    throw InvalidStateError("the simulated camera has no scene yet: arrange one first");
  }
  return environment_.info().world_from_optical;
}

const CameraFrame& SimulatedCameraRig::moveTo(const SphericalPose& goal) {
  environment_.viewFrom(goal);  // throws InvalidStateError before any scene
  return takeFrame();
}

const CameraFrame& SimulatedCameraRig::currentFrame() {
  if (!environment_.hasEpisode()) {
    throw InvalidStateError("the simulated camera has no scene yet: arrange one first");
  }
  return takeFrame();
}

const CameraFrame& SimulatedCameraRig::takeFrame() {
  const Observation& observation = environment_.observation();
  frame_.rgb = observation.rgb;
  frame_.depth = observation.depth;
  if (millimetre_depth_) {
    toMillimetreDepth(observation.depth, millimetres_);
    fromMillimetreDepth(millimetres_, rounded_depth_m_);
    frame_.depth = rounded_depth_m_;
  }
  frame_.intrinsics = environment_.intrinsics();
  frame_.sphere_from_optical = environment_.info().world_from_optical;
  return frame_;
}

}  // namespace occlusion_env
