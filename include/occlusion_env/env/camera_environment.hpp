// The camera bridge's decision logic as an environment (issue 27), free of ROS and libtorch: a
// camera on a rig that moves it on the viewing sphere (CameraRig), the occlusion of each view
// estimated (ViewOcclusionEstimator), and the one episode rule (env/episode_rule.hpp) on the
// estimate. Behind ROS (ros/camera_bridge.hpp) the rig is tf and the camera's topics; in process
// it is the simulator (env/simulated_camera_rig.hpp), so that the episode runner and the tools can
// drive the bridge as they drive the simulator.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/env/environment_interface.hpp"
#include "occlusion_env/env/episode_rule.hpp"
#include "occlusion_env/geometry/camera.hpp"

namespace occlusion_env {

/// One RGB-D frame of a rig, checked by the rig (encodings, sizes, intrinsics). The images are
/// views of the rig's buffers, valid until its next call.
struct CameraFrame {
  cv::Mat rgb;                  // CV_8UC3 rgb8
  cv::Mat depth;                // CV_32FC1 [m], NaN (or 0) = no reading, registered to rgb
  CameraIntrinsics intrinsics;  // of rgb and depth [px]
  Eigen::Isometry3d sphere_from_optical = Eigen::Isometry3d::Identity();  // when it was taken
};

/// A camera that something moves on the viewing sphere: a robot and a real camera, or the
/// simulator standing in for both. Errors are the core's: EnvironmentUnavailableError for a
/// timeout or a camera that cannot be placed, InvalidArgumentError for frames it cannot use.
class CameraRig {
 public:
  virtual ~CameraRig() = default;

  /// Has the scene of `seed` arranged where someone can (the stand-in simulator, a lab
  /// technician; `overrides` as a Reset request's); a rig without one does nothing.
  virtual void arrangeScene(std::uint64_t seed, const ResetOptions& overrides) = 0;

  /// Where the camera's optical frame is now, in the sphere's frame.
  virtual Eigen::Isometry3d cameraPose() = 0;

  /// Sends the camera to `goal` (on the sphere, looking at its centre), waits until it has
  /// arrived and returns the first frame taken after that.
  virtual const CameraFrame& moveTo(const SphericalPose& goal) = 0;

  /// The first frame taken after the last arrangement or move, without moving.
  virtual const CameraFrame& currentFrame() = 0;

  virtual std::string describe() const = 0;
};

/// What a real camera cannot count, estimated from its images (learning/occlusion_estimator.hpp
/// has the network's).
class ViewOcclusionEstimator {
 public:
  virtual ~ViewOcclusionEstimator() = default;
  /// The estimated occlusion of the view [px]; writes `mask` (CV_8UC1 at rgb's size, 255 where
  /// occlusion is estimated; reused).
  /// `intrinsics` are the images' (after any crop).
  virtual std::int64_t estimate(const cv::Mat& rgb, const cv::Mat& depth,
                                const CameraIntrinsics& intrinsics, cv::Mat& mask) = 0;
};

/// Two estimators as one: a pixel is occluded where either estimates occlusion, so a view is
/// clear only where both see none (a second network's opinion: doc/CAMERA_BRIDGE.md, "A second
/// opinion"). The mask is the union of theirs; no allocation once it is sized. Throws
/// InvalidArgumentError without both.
class EstimateUnion : public ViewOcclusionEstimator {
 public:
  EstimateUnion(std::unique_ptr<ViewOcclusionEstimator> first,
                std::unique_ptr<ViewOcclusionEstimator> second);
  std::int64_t estimate(const cv::Mat& rgb, const cv::Mat& depth,
                        const CameraIntrinsics& intrinsics, cv::Mat& mask) override;

 private:
  std::unique_ptr<ViewOcclusionEstimator> first_, second_;
  cv::Mat second_mask_;  // reused
};

/// The bridge's options apart from ROS; the defaults are config/camera_bridge.yaml's. The ROS
/// node's options hold these (ros/camera_bridge.hpp), under the names of
/// cameraEnvironmentOptionTable().
struct CameraEnvironmentOptions {
  double radius_m = 4.0;
  double elevation_limit_rad = 1.3962634016;  // 80 deg
  // The rig's lowest reach (above a floor or a table) [rad]; never below -elevation_limit.
  double lowest_elevation_rad = -1.3962634016;
  double step_size_rad = 0.05;
  bool normalize_action = true;
  bool square_crop = true;  // agents get the central square, as in training
  // A view needs depth within [radius / f, radius * f] (f = working_range_factor) on at least
  // this fraction of the (cropped) view; else it is UNAVAILABLE, never an estimate.
  double min_valid_depth_fraction = 0.02;
  double working_range_factor = 10.0;
  // The stopping rule and reward on the estimate (doc/CAMERA_BRIDGE.md).
  // For the caller's network: a pixel is occluded above it (chosen for the shipped bridge
  // network by occlusion_bridge_calibration: doc/CAMERA_BRIDGE.md, "The default estimate").
  double occlusion_probability = 0.05;
  // For the caller's second network, if it has one (EstimateUnion): a pixel of its map is
  // occluded above this.
  double second_occlusion_probability = 0.2;
  // For the caller's network: estimated occlusion on a floor or wall (occlusion/
  // bounding_surfaces.hpp) is cleared; such a surface shows no object, so none is hidden there.
  bool clear_bounding_surfaces = true;
  std::int64_t occlusion_threshold_px = 0;  // a view is clear at or below this estimate
  int confirm_views = 5;                    // this many clear step views in a row end an episode
  double success_bonus = 5.0;
  double step_penalty = -0.2;
  int max_steps = 50;

  /// The episode rule: intersection-normalised (Z = the reset view's estimate, at least 1: the
  /// union of the silhouettes cannot be estimated), ended by confirm_views clear step views.
  EpisodeRuleOptions rule() const;
  /// Throws InvalidArgumentError naming the first option outside its range (the table's) or a
  /// lowest elevation above the limit.
  void validate() const;
  /// The viewing sphere goals are clamped to: elevations within
  /// [max(lowest_elevation, -elevation_limit), elevation_limit].
  SphericalCamera sphere() const;
};

/// The declared options of CameraEnvironmentOptions, by the camera bridge's parameter names
/// (~radius, ~confirm_views, ...: doc/PARAMETERS.md).
const OptionTable<CameraEnvironmentOptions>& cameraEnvironmentOptionTable();

/// The central square of a width x height image.
cv::Rect centralSquare(int width, int height);

/// The fraction of `depth_m` (NaN or 0 = no reading) within [near_m, far_m]; throws
/// UnusableViewError (an EnvironmentUnavailableError) saying what the view lacks when it is below
/// `min_fraction` or nothing is in range.
double checkDepthCoverage(const cv::Mat& depth_m, double near_m, double far_m, double min_fraction);

class CameraEnvironment : public EnvironmentInterface {
 public:
  /// `rig` and `estimator` must outlive it. Without an estimator (nullptr) the occlusion is
  /// UNAVAILABLE: no reward, and only max_steps ends an episode. Throws InvalidArgumentError for
  /// bad options (validate()).
  CameraEnvironment(const CameraEnvironmentOptions& options, CameraRig& rig,
                    ViewOcclusionEstimator* estimator);

  /// Arranges the scene (where the rig can), moves the camera to the requested start angles if
  /// any (the other angle stays where the camera is) and answers with the first frame after it.
  StepResult reset(std::uint64_t seed, const ResetOptions& overrides = {}) override;

  /// From where the camera is (not where it was sent, so that a robot's errors do not add up),
  /// the action's move on the sphere, and the first frame after the camera has arrived. Every
  /// error leaves the episode as it was.
  StepResult step(const Action& action) override;

  std::string describe() const override { return "camera bridge on " + rig_.describe(); }

  /// Of the last view: the crop of the rig's frame it shows [px], its intrinsics after the crop,
  /// and the fraction of it with depth in the working range.
  const cv::Rect& cropRegion() const { return crop_; }
  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  double validDepthFraction() const { return valid_depth_fraction_; }
  const EpisodeRule& episodeRule() const { return rule_; }
  const CameraEnvironmentOptions& options() const { return options_; }

 private:
  /// The view of `frame`: crops it, checks its depth, estimates its occlusion, into observation_
  /// and `info` (all but the step index). Throws as checkDepthCoverage().
  void takeView(const CameraFrame& frame, StepInfo& info);

  CameraEnvironmentOptions options_;
  CameraRig& rig_;
  ViewOcclusionEstimator* estimator_;
  SphericalCamera sphere_;
  EpisodeRule rule_;
  Observation observation_;
  StepInfo info_;
  cv::Mat mask_;  // the estimate's, reused
  cv::Rect crop_;
  CameraIntrinsics intrinsics_;
  double valid_depth_fraction_ = 0.0;
};

}  // namespace occlusion_env
