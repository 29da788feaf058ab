#include "occlusion_env/occlusion/occlusion_gradient.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

void validateGradientOptions(const OcclusionGradientOptions& options) {
  if (!(std::isfinite(options.blur_sigma_px) && options.blur_sigma_px >= 0.0 &&
        options.blur_sigma_px <= 256.0)) {
    throw InvalidArgumentError("blur_sigma_px must lie in [0, 256] px (0: automatic), got " +
                               std::to_string(options.blur_sigma_px));
  }
  if (!(std::isfinite(options.finite_difference_step_rad) &&
        options.finite_difference_step_rad > 0.0 && options.finite_difference_step_rad <= 0.5)) {
    throw InvalidArgumentError("finite_difference_step_rad must lie in (0, 0.5] rad, got " +
                               std::to_string(options.finite_difference_step_rad));
  }
  if (!(options.zero_gradient_tolerance >= 0.0)) {
    throw InvalidArgumentError("zero_gradient_tolerance must be >= 0 px/rad");
  }
}

namespace {

void checkObjectCount(int num_objects) {
  if (num_objects < 1 || num_objects > kMaxSceneObjects) {
    throw InvalidArgumentError("object count must lie in [1, " + std::to_string(kMaxSceneObjects) +
                               "], got " + std::to_string(num_objects));
  }
}

/// Fills in validity: a gradient is reported only when finite and longer than the tolerance.
void finish(const Eigen::Vector2d& gradient, double tolerance, GradientResult& result) {
  if (!std::isfinite(result.loss)) {
    result.loss = 0.0;
    result.reason = "the loss is not finite";
    return;
  }
  if (!gradient.allFinite()) {
    result.reason = "the gradient is not finite";
    return;
  }
  if (gradient.norm() <= tolerance) {
    result.reason = result.loss > 0.0 ? "zero gradient: the loss is flat to first order here"
                                      : "zero gradient: no blurred silhouettes overlap";
    return;
  }
  result.gradient = gradient;
  result.valid = true;
}

/// Builds (or keeps) the loss workspace for a blur width.
SmoothOcclusionLoss& lossFor(std::unique_ptr<SmoothOcclusionLoss>& loss, double sigma_px) {
  if (!loss || loss->sigmaPx() != sigma_px) loss = std::make_unique<SmoothOcclusionLoss>(sigma_px);
  return *loss;
}

/// Object depth at the surface point behind a boundary-band pixel [m]: the object's own depth
/// where it covers the pixel, else the nearest (smallest) depth among its 3 x 3 neighbours that
/// it covers; NaN when there is none.
float surfaceDepth(const cv::Mat& object_depth, int row, int col) {
  const float own = object_depth.at<float>(row, col);
  if (std::isfinite(own)) return own;
  float nearest = std::numeric_limits<float>::infinity();
  for (int r = std::max(row - 1, 0); r <= std::min(row + 1, object_depth.rows - 1); ++r) {
    const float* depth = object_depth.ptr<float>(r);
    for (int c = std::max(col - 1, 0); c <= std::min(col + 1, object_depth.cols - 1); ++c) {
      if (std::isfinite(depth[c])) nearest = std::min(nearest, depth[c]);
    }
  }
  return std::isfinite(nearest) ? nearest : std::numeric_limits<float>::quiet_NaN();
}

}  // namespace

double blurSigmaFor(const OcclusionGradientOptions& options, int width_px) {
  return options.blur_sigma_px > 0.0 ? options.blur_sigma_px : width_px * 3.0 / 64.0;
}

// --- SmoothOcclusionLoss ------------------------------------------------------------------------

SmoothOcclusionLoss::SmoothOcclusionLoss(double sigma_px) : sigma_px_(sigma_px) {
  if (!(std::isfinite(sigma_px) && sigma_px > 0.0 && sigma_px <= 256.0)) {
    throw InvalidArgumentError("blur sigma must lie in (0, 256] px, got " +
                               std::to_string(sigma_px));
  }
}

void SmoothOcclusionLoss::blur(const cv::Mat& in, cv::Mat& out) const {
  // Zero outside the image: the operator is then symmetric, so the same blur is its own adjoint
  // (the analytic gradient relies on that).
  const double sigma = sigma_px_ / factor_;
  cv::GaussianBlur(in, out, kernel_size_, sigma, sigma, cv::BORDER_CONSTANT);
}

double SmoothOcclusionLoss::evaluate(const cv::Mat& amodal_bits, int num_objects) {
  if (amodal_bits.type() != CV_8UC1 || amodal_bits.empty()) {
    throw InvalidArgumentError("amodal bits must be a non-empty CV_8UC1 image");
  }
  checkObjectCount(num_objects);
  const cv::Size size = amodal_bits.size();
  factor_ = 1;
  for (int factor : {4, 2}) {
    if (sigma_px_ >= 1.5 * factor && size.width % factor == 0 && size.height % factor == 0) {
      factor_ = factor;
      break;
    }
  }
  const int radius = static_cast<int>(std::ceil(3.0 * sigma_px_ / factor_));  // cut at 3 sigma
  kernel_size_ = cv::Size(2 * radius + 1, 2 * radius + 1);
  const cv::Size coarse_size(size.width / factor_, size.height / factor_);

  for (int k = 0; k < num_objects; ++k) masks_[k].create(size, CV_32FC1);
  int covered[kMaxSceneObjects] = {};
  for (int row = 0; row < size.height; ++row) {
    const std::uint8_t* bits = amodal_bits.ptr<std::uint8_t>(row);
    for (int k = 0; k < num_objects; ++k) {
      float* mask = masks_[k].ptr<float>(row);
      int count = 0;
      for (int col = 0; col < size.width; ++col) {
        const int inside = (bits[col] >> k) & 1;
        mask[col] = static_cast<float>(inside);
        count += inside;
      }
      covered[k] += count;
    }
  }
  smoothed_sum_.create(coarse_size, CV_32FC1);
  smoothed_sum_.setTo(0);
  for (int k = 0; k < num_objects; ++k) {
    smoothed_[k].create(coarse_size, CV_32FC1);
    if (covered[k] == 0) {
      smoothed_[k].setTo(0);
      continue;
    }
    if (factor_ == 1) {
      blur(masks_[k], smoothed_[k]);
    } else {
      cv::resize(masks_[k], coarse_mask_, coarse_size, 0.0, 0.0, cv::INTER_AREA);  // block mean
      blur(coarse_mask_, smoothed_[k]);
    }
    smoothed_sum_ += smoothed_[k];
  }
  double loss = 0.0;
  for (int i = 0; i < num_objects; ++i) {
    if (covered[i] == 0) continue;
    for (int j = i + 1; j < num_objects; ++j) {
      if (covered[j] > 0) loss += smoothed_[i].dot(smoothed_[j]);
    }
  }
  return loss * factor_ * factor_;
}

// --- The camera's motion ------------------------------------------------------------------------

namespace {

/// The rotation's and centre's derivatives with respect to (azimuth, elevation), in the form the
/// per-pixel loop needs: d(point_optical)/dq = spin[q] * point_optical - shift[q].
struct CameraMotion {
  Eigen::Matrix3d spin[2];   // dR^T/dq R (skew-symmetric) [1/rad]
  Eigen::Vector3d shift[2];  // R^T dc/dq [m/rad]
};

CameraMotion cameraMotion(const SphericalCamera& camera, const SphericalPose& pose) {
  const double ca = std::cos(pose.azimuth_rad), sa = std::sin(pose.azimuth_rad);
  const double ce = std::cos(pose.elevation_rad), se = std::sin(pose.elevation_rad);
  const double r = camera.radius();
  // Columns: the optical x (right = -left), y (down = -up) and z (forward) axes in the world,
  // as SphericalCamera::worldFromOptical builds them, and their derivatives.
  Eigen::Matrix3d rotation, d_rotation[2];
  rotation << -sa, se * ca, -ce * ca,  //
      ca, se * sa, -ce * sa,           //
      0.0, -ce, -se;
  d_rotation[0] << -ca, -se * sa, ce * sa,  //
      -sa, se * ca, -ce * ca,               //
      0.0, 0.0, 0.0;
  d_rotation[1] << 0.0, ce * ca, se * ca,  //
      0.0, ce * sa, se * sa,               //
      0.0, se, -ce;
  const Eigen::Vector3d d_centre[2] = {r * Eigen::Vector3d(-ce * sa, ce * ca, 0.0),
                                       r * Eigen::Vector3d(-se * ca, -se * sa, ce)};
  CameraMotion motion;
  for (int q = 0; q < 2; ++q) {
    motion.spin[q] = d_rotation[q].transpose() * rotation;
    motion.shift[q] = rotation.transpose() * d_centre[q];
  }
  return motion;
}

}  // namespace

Eigen::Matrix<double, 3, 2> opticalPointDerivative(const SphericalCamera& camera,
                                                   const SphericalPose& pose,
                                                   const Eigen::Vector3d& point_optical) {
  const CameraMotion motion = cameraMotion(camera, pose);
  Eigen::Matrix<double, 3, 2> derivative;
  for (int q = 0; q < 2; ++q) {
    derivative.col(q) = motion.spin[q] * point_optical - motion.shift[q];
  }
  return derivative;
}

// --- Analytic gradient --------------------------------------------------------------------------

AnalyticOcclusionGradient::AnalyticOcclusionGradient(const OcclusionGradientOptions& options)
    : options_(options) {
  validateGradientOptions(options);
}

GradientResult AnalyticOcclusionGradient::compute(RenderedView& view) {
  if (!view.hasView()) {
    GradientResult result;
    result.reason = "no episode: call reset first";
    return result;
  }
  return compute(view.renderBuffers(), view.numObjects(), view.intrinsics(), view.camera(),
                 view.pose());
}

GradientResult AnalyticOcclusionGradient::compute(const RenderBuffers& buffers, int num_objects,
                                                  const CameraIntrinsics& intrinsics,
                                                  const SphericalCamera& camera,
                                                  const SphericalPose& pose) {
  checkObjectCount(num_objects);
  const cv::Size size(intrinsics.width, intrinsics.height);
  if (buffers.amodal_bits.size() != size ||
      buffers.object_depth.size() < static_cast<std::size_t>(num_objects)) {
    throw InvalidArgumentError("render buffers do not match the intrinsics and object count");
  }
  for (int k = 0; k < num_objects; ++k) {
    if (buffers.object_depth[k].type() != CV_32FC1 || buffers.object_depth[k].size() != size) {
      throw InvalidArgumentError("object depth " + std::to_string(k) +
                                 " must be CV_32FC1 of the image's size");
    }
  }
  if (!std::isfinite(pose.azimuth_rad) || !std::isfinite(pose.elevation_rad)) {
    throw InvalidArgumentError("pose must be finite");
  }

  SmoothOcclusionLoss& loss = lossFor(loss_, blurSigmaFor(options_, intrinsics.width));
  GradientResult result;
  result.loss = loss.evaluate(buffers.amodal_bits, num_objects);
  skipped_boundary_pixels_ = 0;
  if (num_objects < 2) {
    result.reason = "fewer than two objects: nothing can overlap";
    return result;
  }

  // dL_s/dq = sum_k sum_p W_k(p) dM_k(p)/dq, W_k = G * sum_{j != k} S_j (G is its own adjoint),
  // and a silhouette carried by the image velocity v_k changes as dM_k/dq = -grad M_k . v_k.
  const CameraMotion motion = cameraMotion(camera, pose);
  const double fx = intrinsics.fx, fy = intrinsics.fy, cx = intrinsics.cx, cy = intrinsics.cy;
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
  for (int k = 0; k < num_objects; ++k) {
    const cv::Mat& mask = loss.mask(k);
    if (cv::countNonZero(mask) == 0) continue;
    // The adjoint of the block mean times f^2 copies each coarse value to its f x f block.
    cv::subtract(loss.smoothedSum(), loss.smoothed(k), others_smoothed_);
    loss.blur(others_smoothed_, coarse_weight_);
    cv::resize(coarse_weight_, weight_, size, 0.0, 0.0, cv::INTER_NEAREST);
    // Central differences across the boundary (Sobel / 8) sum to exactly the jump of the mask
    // along every row and column. Replicated borders: a silhouette cut by the image edge has no
    // boundary there (it does not move into or out of the image at the edge).
    cv::Sobel(mask, mask_du_, CV_32F, 1, 0, 3, 1.0 / 8.0, 0.0, cv::BORDER_REPLICATE);
    cv::Sobel(mask, mask_dv_, CV_32F, 0, 1, 3, 1.0 / 8.0, 0.0, cv::BORDER_REPLICATE);
    const cv::Mat& object_depth = buffers.object_depth[k];
    Eigen::Vector2d object_gradient = Eigen::Vector2d::Zero();
    for (int row = 0; row < size.height; ++row) {
      const float* du_row = mask_du_.ptr<float>(row);
      const float* dv_row = mask_dv_.ptr<float>(row);
      const float* weight_row = weight_.ptr<float>(row);
      for (int col = 0; col < size.width; ++col) {
        const double mask_du = du_row[col], mask_dv = dv_row[col], weight = weight_row[col];
        if ((mask_du == 0.0 && mask_dv == 0.0) || weight == 0.0) continue;
        const float depth = surfaceDepth(object_depth, row, col);
        if (!(depth > 0.0f)) {
          ++skipped_boundary_pixels_;
          continue;
        }
        const Eigen::Vector3d point(depth * (col - cx) / fx, depth * (row - cy) / fy, depth);
        for (int q = 0; q < 2; ++q) {
          const Eigen::Vector3d d_point = motion.spin[q] * point - motion.shift[q];
          const double du = fx * (d_point.x() - point.x() * d_point.z() / depth) / depth;
          const double dv = fy * (d_point.y() - point.y() * d_point.z() / depth) / depth;
          object_gradient[q] -= weight * (mask_du * du + mask_dv * dv);
        }
      }
    }
    gradient += object_gradient;
  }
  finish(gradient, options_.zero_gradient_tolerance, result);
  return result;
}

// --- Finite differences -------------------------------------------------------------------------

FiniteDifferenceOcclusionGradient::FiniteDifferenceOcclusionGradient(
    const OcclusionGradientOptions& options)
    : options_(options) {
  validateGradientOptions(options);
}

GradientResult FiniteDifferenceOcclusionGradient::compute(RenderedView& view) {
  GradientResult result;
  if (!view.hasView()) {
    result.reason = "no episode: call reset first";
    return result;
  }
  const int num_objects = view.numObjects();
  SmoothOcclusionLoss& loss = lossFor(loss_, blurSigmaFor(options_, view.intrinsics().width));
  result.loss = loss.evaluate(view.renderBuffers().amodal_bits, num_objects);
  if (num_objects < 2) {
    result.reason = "fewer than two objects: nothing can overlap";
    return result;
  }
  const SphericalPose pose = view.pose();
  const double h = options_.finite_difference_step_rad;
  const auto loss_at = [&](double azimuth, double elevation) {
    return loss.evaluate(view.renderAt({azimuth, elevation}).amodal_bits, num_objects);
  };
  Eigen::Vector2d gradient;
  gradient[0] = (loss_at(pose.azimuth_rad + h, pose.elevation_rad) -
                 loss_at(pose.azimuth_rad - h, pose.elevation_rad)) /
                (2.0 * h);
  // renderAt clamps the elevation: difference over the part of [e - h, e + h] within the range.
  const double upper = std::min(pose.elevation_rad + h, view.camera().highestElevation());
  const double lower = std::max(pose.elevation_rad - h, view.camera().lowestElevation());
  gradient[1] =
      upper > lower
          ? (loss_at(pose.azimuth_rad, upper) - loss_at(pose.azimuth_rad, lower)) / (upper - lower)
          : 0.0;
  finish(gradient, options_.zero_gradient_tolerance, result);
  return result;
}

// --- Factories ----------------------------------------------------------------------------------

std::unique_ptr<OcclusionGradient> makeAnalyticGradient(const OcclusionGradientOptions& options) {
  return std::make_unique<AnalyticOcclusionGradient>(options);
}

std::unique_ptr<OcclusionGradient> makeFiniteDifferenceGradient(
    const OcclusionGradientOptions& options) {
  return std::make_unique<FiniteDifferenceOcclusionGradient>(options);
}

std::unique_ptr<OcclusionGradient> makeOcclusionGradient(const std::string& method,
                                                         const OcclusionGradientOptions& options) {
  if (method == "analytic") return makeAnalyticGradient(options);
  if (method == "finite_difference") return makeFiniteDifferenceGradient(options);
  throw InvalidArgumentError("gradient method must be analytic or finite_difference, got " +
                             quoted(method));
}

}  // namespace occlusion_env
