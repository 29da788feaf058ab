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

BridgedSimulator::BridgedSimulator(Environment& simulator, CameraEnvironmentOptions options,
                                   ViewOcclusionEstimator* estimator, bool millimetre_depth)
    : simulator_(simulator),
      rig_(simulator, millimetre_depth),
      bridge_(onTheSimulatorsSphere(simulator, std::move(options)), rig_, estimator) {}

double BridgedSimulator::sphereRadius(const EnvironmentOptions& options) {
  const CameraRandomization& drawn = options.camera_randomization;
  if (!drawn.enabled) return options.radius_m;
  // The rest of the camera may be drawn per scene (field of view, resolution, intrinsics: the
  // bridge reads them from each frame), but its sphere is fixed.
  if (drawn.radius_range_m.size() != 2 || drawn.radius_range_m[0] != drawn.radius_range_m[1]) {
    throw InvalidArgumentError(
        "the camera bridge needs one camera radius (its sphere is fixed): give the camera "
        "randomisation one radius (radius_range r,r) or switch it off");
  }
  return drawn.radius_range_m[0];
}

CameraEnvironmentOptions BridgedSimulator::onTheSimulatorsSphere(const Environment& simulator,
                                                                 CameraEnvironmentOptions options) {
  const EnvironmentOptions& simulated = simulator.options();
  options.radius_m = sphereRadius(simulated);
  options.elevation_limit_rad = simulated.elevation_limit_rad;
  options.step_size_rad = simulated.step_size_rad;
  options.normalize_action = simulated.normalize_action;
  options.max_steps = simulated.max_steps;
  return options;
}

}  // namespace occlusion_env
