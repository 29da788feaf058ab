#include "occlusion_env/env/camera_environment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

std::string percent(double fraction) {
  std::ostringstream text;
  text.precision(3);
  text << fraction * 100.0 << " %";
  return text.str();
}

}  // namespace

const OptionTable<CameraEnvironmentOptions>& cameraEnvironmentOptionTable() {
  using Options = CameraEnvironmentOptions;
  static const auto table = [] {
    OptionTable<Options> made;
    // The viewing sphere and the episodes, as the simulator's.
    made.add("radius", &Options::radius_m,
             OptionSpec("the camera stays this far from the centre").unit("m").above(0))
        .add("elevation_limit", &Options::elevation_limit_rad,
             OptionSpec("goals are clamped to +/- this elevation (80 deg)")
                 .unit("rad")
                 .atLeast(0)
                 .below(M_PI / 2.0))
        .add("lowest_elevation", &Options::lowest_elevation_rad,
             OptionSpec("goals are clamped to at least this elevation, the rig's lowest reach "
                        "(e.g. above a floor or a table); never below -elevation_limit")
                 .unit("rad")
                 .above(-M_PI / 2.0)
                 .below(M_PI / 2.0))
        .add("step_size", &Options::step_size_rad,
             OptionSpec("unit step").unit("rad").above(0).atMost(M_PI))
        .add("normalize_action", &Options::normalize_action,
             OptionSpec("true: each step moves exactly step_size along the action; false: the "
                        "action as given, clipped to length step_size"))
        .add("max_steps", &Options::max_steps,
             OptionSpec("steps before an episode is truncated").atLeast(1));
    // Which views are used.
    made.add("square_crop", &Options::square_crop,
             OptionSpec("agents get the central square of the images (as trained); "
                        "camera_info's principal point is moved to match"))
        .add("min_valid_depth_fraction", &Options::min_valid_depth_fraction,
             OptionSpec("a view with depth within the working range on less of its pixels is "
                        "not used (UNAVAILABLE): a covered lens, a camera too close, depth in "
                        "another unit")
                 .above(0)
                 .atMost(1))
        .add("working_range_factor", &Options::working_range_factor,
             OptionSpec("depth readings count within [radius / this, radius * this]").atLeast(1));
    // The estimate, the stopping rule and the reward.
    made.add("occlusion_probability", &Options::occlusion_probability,
             OptionSpec("a pixel counts as occluded above this probability").above(0).below(1))
        .add("second_occlusion_probability", &Options::second_occlusion_probability,
             OptionSpec("with a second network (the bridge's second_model): a pixel counts as "
                        "occluded above this probability of its map too")
                 .above(0)
                 .below(1))
        .add("occlusion_threshold", &Options::occlusion_threshold_px,
             OptionSpec("a view whose estimate is at or below this is clear").unit("px").atLeast(0))
        .add("confirm_views", &Options::confirm_views,
             OptionSpec("this many clear views in a row end the episode (terminated)").atLeast(1))
        .add("clear_bounding_surfaces", &Options::clear_bounding_surfaces,
             OptionSpec("estimated occlusion on a floor or wall (a large plane in the depth "
                        "with nothing seen behind it) is cleared: such a surface hides nothing"))
        .add("success_bonus", &Options::success_bonus,
             OptionSpec("reward P when the episode ends: R_t = (L_{t-1} - L_t) / max(1, L_0) + P"))
        .add("step_penalty", &Options::step_penalty, OptionSpec("reward P of the other steps"));
    return made;
  }();
  return table;
}

void CameraEnvironmentOptions::validate() const {
  cameraEnvironmentOptionTable().check(*this);
  if (!(lowest_elevation_rad <= elevation_limit_rad)) {
    throw InvalidArgumentError("option 'lowest_elevation' (" +
                               std::to_string(lowest_elevation_rad) +
                               " rad) must not lie above elevation_limit (" +
                               std::to_string(elevation_limit_rad) + " rad)");
  }
}

SphericalCamera CameraEnvironmentOptions::sphere() const {
  return SphericalCamera(radius_m, std::max(lowest_elevation_rad, -elevation_limit_rad),
                         elevation_limit_rad);
}

EpisodeRuleOptions CameraEnvironmentOptions::rule() const {
  EpisodeRuleOptions rule;
  rule.reward.normalization = RewardNormalization::kIntersection;
  rule.reward.success_bonus = success_bonus;
  rule.reward.step_penalty = step_penalty;
  rule.reward.success_threshold_pixels = occlusion_threshold_px;
  rule.max_steps = max_steps;
  rule.confirm_views = confirm_views;
  return rule;
}

EstimateUnion::EstimateUnion(std::unique_ptr<ViewOcclusionEstimator> first,
                             std::unique_ptr<ViewOcclusionEstimator> second)
    : first_(std::move(first)), second_(std::move(second)) {
  if (!first_ || !second_) throw InvalidArgumentError("EstimateUnion: needs two estimators");
}

std::int64_t EstimateUnion::estimate(const cv::Mat& rgb, const cv::Mat& depth,
                                     const CameraIntrinsics& intrinsics, cv::Mat& mask) {
  first_->estimate(rgb, depth, intrinsics, mask);
  second_->estimate(rgb, depth, intrinsics, second_mask_);
  cv::bitwise_or(mask, second_mask_, mask);
  return cv::countNonZero(mask);
}

cv::Rect centralSquare(int width, int height) {
  const int side = std::min(width, height);
  return {(width - side) / 2, (height - side) / 2, side, side};
}

double checkDepthCoverage(const cv::Mat& depth_m, double near_m, double far_m,
                          double min_fraction) {
  std::int64_t readings = 0, in_range = 0;
  float nearest_m = std::numeric_limits<float>::infinity(), farthest_m = 0.0f;
  for (int row = 0; row < depth_m.rows; ++row) {
    const float* depth = depth_m.ptr<float>(row);
    for (int col = 0; col < depth_m.cols; ++col) {
      if (!(depth[col] > 0.0f)) continue;  // NaN: no reading
      ++readings;
      in_range += depth[col] >= near_m && depth[col] <= far_m;
      nearest_m = std::min(nearest_m, depth[col]);
      farthest_m = std::max(farthest_m, depth[col]);
    }
  }
  const double fraction = static_cast<double>(in_range) / std::max<double>(1.0, depth_m.total());
  if (in_range > 0 && fraction >= min_fraction) return fraction;
  std::ostringstream text;
  if (readings == 0) {
    text << "no valid depth in the view (all NaN or 0: a covered lens, a camera closer than its "
            "minimum range, a black or reflective scene)";
  } else {
    text << "only " << percent(fraction) << " of the view has depth within the working range ["
         << near_m << ", " << far_m << "] m; its readings lie in [" << nearest_m << ", "
         << farthest_m << "] m (depth in another unit than its encoding says, or a camera that "
         << "does not look at the scene?)";
  }
  text << "; a view is used when at least " << percent(min_fraction)
       << " of it has depth in the working range (~min_valid_depth_fraction, ~radius / "
          "~working_range_factor to ~radius * ~working_range_factor)";
  throw UnusableViewError(text.str());
}

CameraEnvironment::CameraEnvironment(const CameraEnvironmentOptions& options, CameraRig& rig,
                                     ViewOcclusionEstimator* estimator)
    : options_((options.validate(), options)),  // before the sphere is made of them
      rig_(rig),
      estimator_(estimator),
      sphere_(options.sphere()),
      rule_(options.rule()) {}

void CameraEnvironment::takeView(const CameraFrame& frame, StepInfo& info) {
  if (frame.rgb.empty() || frame.rgb.size() != frame.depth.size() || frame.rgb.type() != CV_8UC3 ||
      frame.depth.type() != CV_32FC1) {
    throw InvalidArgumentError("the camera rig gave no rgb8 + 32FC1 frame of one size");
  }
  const cv::Rect crop = options_.square_crop ? centralSquare(frame.rgb.cols, frame.rgb.rows)
                                             : cv::Rect(0, 0, frame.rgb.cols, frame.rgb.rows);
  const cv::Mat depth = frame.depth(crop);
  const double valid_depth_fraction = checkDepthCoverage(
      depth, options_.radius_m / options_.working_range_factor,
      options_.radius_m * options_.working_range_factor, options_.min_valid_depth_fraction);

  // The view is usable: only now does anything the last answer showed change.
  crop_ = crop;
  valid_depth_fraction_ = valid_depth_fraction;
  intrinsics_ = frame.intrinsics;
  intrinsics_.width = crop.width;  // the crop moves the principal point, not the focal lengths
  intrinsics_.height = crop.height;
  intrinsics_.cx -= crop.x;
  intrinsics_.cy -= crop.y;
  observation_.rgb = frame.rgb(crop);
  observation_.depth = depth;
  observation_.instance = cv::Mat();  // a camera does not know the objects
  observation_.amodal_bits = cv::Mat();

  OcclusionStats& occlusion = info.occlusion;
  occlusion.pairs.clear();
  if (estimator_) {
    // The network predicts where silhouettes overlap, not how many overlap there: the area stands
    // for L as well.
    const std::int64_t estimate =
        estimator_->estimate(observation_.rgb, observation_.depth, intrinsics_, mask_);
    occlusion.total_pixels = occlusion.occluded_area_pixels = estimate;
    occlusion.union_pixels = kUnknownOcclusion;
    info.occlusion_source = OcclusionSource::kEstimated;
    observation_.occlusion_mask = mask_;
  } else {
    occlusion.total_pixels = occlusion.occluded_area_pixels = occlusion.union_pixels =
        kUnknownOcclusion;
    info.occlusion_source = OcclusionSource::kUnavailable;
    observation_.occlusion_mask = cv::Mat();
  }
  info.world_from_optical = frame.sphere_from_optical;
  info.pose = sphericalPoseOf(frame.sphere_from_optical.translation());
  info.intrinsics = intrinsics_;
}

StepResult CameraEnvironment::reset(std::uint64_t seed, const ResetOptions& overrides) {
  // A request the bridge would refuse arranges no scene.
  const auto& azimuth = overrides.start_azimuth_rad;
  const auto& elevation = overrides.start_elevation_rad;
  if ((azimuth && !std::isfinite(*azimuth)) || (elevation && !std::isfinite(*elevation))) {
    throw InvalidArgumentError("start azimuth and elevation must be finite");
  }
  if (elevation &&
      !(*elevation >= sphere_.lowestElevation() && *elevation <= sphere_.highestElevation())) {
    throw InvalidArgumentError(
        "start elevation must lie within [lowest_elevation, "
        "elevation_limit] (the lowest never below -elevation_limit)");
  }
  rig_.arrangeScene(seed, overrides);
  const CameraFrame* frame = nullptr;
  if (azimuth || elevation) {
    // Where the camera is now (after the arrangement, which may have moved it).
    const SphericalPose now = sphericalPoseOf(rig_.cameraPose().translation());
    frame = &rig_.moveTo(sphere_.normalized(
        {azimuth.value_or(now.azimuth_rad), elevation.value_or(now.elevation_rad)}));
  } else {
    frame = &rig_.currentFrame();
  }
  StepInfo info = info_;
  takeView(*frame, info);
  info.last_action = Action{};
  rule_.start(info.occlusion);
  info_ = std::move(info);
  info_.step_index = rule_.stepIndex();
  StepResult result;
  result.observation = &observation_;
  result.info = info_;
  return result;
}

StepResult CameraEnvironment::step(const Action& action) {
  rule_.requireStep();
  const Action move = cameraMoveFor(action, options_.step_size_rad, options_.normalize_action);
  const SphericalPose now = sphericalPoseOf(rig_.cameraPose().translation());
  const CameraFrame& frame =
      rig_.moveTo(sphere_.moved(now, move.d_azimuth_rad, move.d_elevation_rad));
  StepInfo info = info_;
  takeView(frame, info);
  info.last_action = action;
  // Only now does the episode change: every error above leaves it as it was.
  const StepVerdict verdict = rule_.step(info.occlusion.total_pixels);
  info_ = std::move(info);
  info_.step_index = rule_.stepIndex();
  StepResult result;
  result.observation = &observation_;
  result.reward = verdict.reward;
  result.terminated = verdict.terminated;
  result.truncated = verdict.truncated;
  result.info = info_;
  return result;
}

}  // namespace occlusion_env
