// The simulator as a camera rig (env/camera_environment.hpp): the stand-in camera of
// ros/stand_in_camera.hpp in process, so that the camera bridge's logic runs on the simulator's
// scenes without ROS. Arranging a scene resets the simulator; a move renders the view at the goal
// at once (Environment::viewFrom); frames carry only what a camera gives (RGB, depth through the
// scene's depth sensor, intrinsics, pose). The truth stays in the Environment, for scoring.
#pragma once

#include <string>

#include "occlusion_env/env/camera_environment.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {

class SimulatedCameraRig : public CameraRig {
 public:
  /// `environment` must outlive the rig. With `millimetre_depth` depth is rounded to whole
  /// millimetres as a 16UC1 camera sends it (the stand-in's ~depth_encoding 16UC1).
  explicit SimulatedCameraRig(Environment& environment, bool millimetre_depth = false);

  void arrangeScene(std::uint64_t seed, const ResetOptions& overrides) override;
  /// InvalidStateError before the first arrangement.
  Eigen::Isometry3d cameraPose() override;
  const CameraFrame& moveTo(const SphericalPose& goal) override;
  const CameraFrame& currentFrame() override;
  std::string describe() const override { return "the in-process simulator as a camera"; }

  Environment& environment() { return environment_; }

 private:
  /// The frame of the environment's current view.
  const CameraFrame& takeFrame();

  Environment& environment_;
  bool millimetre_depth_;
  CameraFrame frame_;
  cv::Mat millimetres_, rounded_depth_m_;  // reused with millimetre_depth
};

/// The camera bridge's logic in front of the simulator, in process (what camera_bridge.launch
/// stand_in:=true runs over ROS): the bridge's sphere, step and limits are the simulator's, its
/// rule and estimator as given. The simulator's truth scores where the bridge's camera is.
class BridgedSimulator {
 public:
  /// `simulator` and `estimator` must outlive this. The bridge's sphere is the simulator's, or
  /// the one radius its camera randomisation draws (the rest of the camera, such as the field of
  /// view, may be drawn per scene). Throws InvalidArgumentError when it draws the radius from a
  /// range (the bridge's sphere is fixed).
  BridgedSimulator(Environment& simulator, CameraEnvironmentOptions options,
                   ViewOcclusionEstimator* estimator, bool millimetre_depth = false);

  /// The radius [m] of the sphere the bridge works on in front of a simulator with `options`:
  /// theirs, or the one radius their camera randomisation draws. Throws InvalidArgumentError
  /// when that draws the radius from a range (the bridge's sphere is fixed).
  static double sphereRadius(const EnvironmentOptions& options);

  /// What agents act on.
  CameraEnvironment& bridge() { return bridge_; }
  /// The simulator's occlusion L of the view the camera has now [px], and whether it is clear.
  std::int64_t trueOcclusion() const { return simulator_.info().occlusion.total_pixels; }
  bool trulyClear() const { return simulator_.reward().solved(trueOcclusion()); }

 private:
  static CameraEnvironmentOptions onTheSimulatorsSphere(const Environment& simulator,
                                                        CameraEnvironmentOptions options);

  Environment& simulator_;
  SimulatedCameraRig rig_;
  CameraEnvironment bridge_;
};

}  // namespace occlusion_env
