// The smooth occlusion loss and its gradient with respect to the camera angles (Section 4 of the
// paper). Derivation and the choices behind it: doc/GRADIENT.md.
//
//   L_s = sum over pairs i < j, sum over pixels p of S_i(p) S_j(p)   [px],
//   S_i = G_sigma * M_i (object i's amodal silhouette blurred by a Gaussian, zero outside the
//   image), so that L_s keeps a slope when one silhouette lies entirely inside another.
//
// Two methods give dL_s/d(azimuth, elevation) [px/rad] behind one interface: an analytic one from
// the buffers of the current render (no re-rendering) and central finite differences that
// re-render at +/- h (Environment::renderAt; the episode is not changed).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "occlusion_env/geometry/camera.hpp"
#include "occlusion_env/render/renderer.hpp"

namespace occlusion_env {

/// What a gradient needs of a rendered view: its buffers, its camera and the means to render the
/// same scene from nearby poses. The in-process Environment is one; hand-made views are others.
class RenderedView {
 public:
  virtual ~RenderedView() = default;
  /// False before any view exists (e.g. before the first reset).
  virtual bool hasView() const = 0;
  virtual const RenderBuffers& renderBuffers() const = 0;
  virtual int numObjects() const = 0;
  virtual const CameraIntrinsics& intrinsics() const = 0;
  virtual const SphericalCamera& camera() const = 0;
  virtual SphericalPose pose() const = 0;
  /// Renders the same scene from `pose` without changing the view, into separate buffers.
  virtual const RenderBuffers& renderAt(const SphericalPose& pose) = 0;
};

struct OcclusionGradientOptions {
  /// Width of the Gaussian that smooths each silhouette [px]; 0 picks width * 3 / 64 (12 px at
  /// 256 x 256, 6 px at 128 x 128), so the loss is the same function of the view at any
  /// resolution up to a factor (resolution / 256)^2. The kernel is cut at 3 sigma.
  double blur_sigma_px = 0.0;
  /// Finite differences: the angle step h [rad] of the central difference. Rasterised masks change
  /// in whole-pixel jumps (an edge parallel to a pixel column gains or loses a column at once),
  /// so L_s is a staircase in the angles and h must span a few pixels of motion: 0.02 rad moves
  /// the near objects of the default scene (r = 4 m, 60 deg field of view, 256 px) by about
  /// 1.5-4 px, still well inside the blur's 12 px. See doc/GRADIENT.md.
  double finite_difference_step_rad = 0.02;
  /// A gradient whose length is at or below this [px/rad] is reported as zero (invalid).
  double zero_gradient_tolerance = 1e-9;
};

/// Throws InvalidArgumentError naming the first option out of range.
void validateGradientOptions(const OcclusionGradientOptions& options);

/// The loss and its gradient. `gradient` is (dL_s/d azimuth, dL_s/d elevation) [px/rad]; it is
/// zero whenever `valid` is false, and `reason` then says why (no overlap within reach of the
/// blur, fewer than two objects, no episode, ...). Never NaN.
struct GradientResult {
  double loss = 0.0;  // L_s [px]
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
  bool valid = false;
  std::string reason;
};

/// Evaluates L_s from amodal silhouettes, keeping its images in buffers that later calls reuse.
/// The blur runs on a grid coarser by an integer factor f (4 when sigma >= 6 px, 2 when sigma >=
/// 3 px, where the image size allows; else 1): S_k = G_{sigma/f} * (M_k averaged over f x f
/// blocks), L_s = f^2 sum over coarse pixels of S_i S_j. The wide Gaussian makes the coarse grid
/// lose nothing that matters, and the blur costs 1/f^2 of a full-resolution one.
class SmoothOcclusionLoss {
 public:
  /// Throws InvalidArgumentError unless 0 < sigma_px <= 256.
  explicit SmoothOcclusionLoss(double sigma_px);

  double sigmaPx() const { return sigma_px_; }

  /// L_s [px] of `amodal_bits` (CV_8UC1, bit k = object k) for `num_objects` objects (1..8).
  /// Throws InvalidArgumentError on a wrong image type or object count.
  double evaluate(const cv::Mat& amodal_bits, int num_objects);

  /// After evaluate(): the coarse grid's factor f, object k's full-resolution mask M_k
  /// (CV_32FC1, 0 or 1), its blurred mask S_k and the sum over k of S_k (CV_32FC1, coarse grid).
  int factor() const { return factor_; }
  const cv::Mat& mask(int k) const { return masks_[k]; }
  const cv::Mat& smoothed(int k) const { return smoothed_[k]; }
  const cv::Mat& smoothedSum() const { return smoothed_sum_; }
  /// Blurs `in` (coarse grid) with the loss's Gaussian, zero outside the image, into `out`.
  void blur(const cv::Mat& in, cv::Mat& out) const;

 private:
  double sigma_px_;
  int factor_ = 1;
  cv::Size kernel_size_;
  cv::Mat masks_[kMaxSceneObjects];
  cv::Mat coarse_mask_;
  cv::Mat smoothed_[kMaxSceneObjects];
  cv::Mat smoothed_sum_;
};

/// The blur width `options` give for an image `width_px` wide [px].
double blurSigmaFor(const OcclusionGradientOptions& options, int width_px);

/// d(point in the optical frame)/d(azimuth, elevation) for a point fixed in the world, as the
/// camera moves on its sphere: column 0 per radian of azimuth, column 1 per radian of elevation.
/// `point_optical` is the point in the optical frame at `pose`. Closed form of SphericalCamera's
/// look-at pose (the clamp and wrap of normalized() are not applied).
Eigen::Matrix<double, 3, 2> opticalPointDerivative(const SphericalCamera& camera,
                                                   const SphericalPose& pose,
                                                   const Eigen::Vector3d& point_optical);

/// Where the gradient comes from: analytic or finite differences, selectable behind this
/// interface. compute() works on a view's current render and leaves it unchanged (finite
/// differences render into the view's probe buffers).
class OcclusionGradient {
 public:
  virtual ~OcclusionGradient() = default;
  virtual GradientResult compute(RenderedView& view) = 0;
  virtual std::string name() const = 0;
};

/// The analytic gradient from one render's buffers. Also usable on hand-made buffers.
class AnalyticOcclusionGradient : public OcclusionGradient {
 public:
  explicit AnalyticOcclusionGradient(const OcclusionGradientOptions& options = {});

  GradientResult compute(RenderedView& view) override;
  std::string name() const override { return "analytic"; }

  /// L_s and its gradient for the view `buffers` show: the camera at `pose` on `camera`'s sphere,
  /// with `intrinsics`. Uses amodal_bits and object_depth[0 .. num_objects - 1].
  /// Throws InvalidArgumentError on inconsistent buffers.
  GradientResult compute(const RenderBuffers& buffers, int num_objects,
                         const CameraIntrinsics& intrinsics, const SphericalCamera& camera,
                         const SphericalPose& pose);

  /// Boundary pixels of the last compute() whose surface point could not be found (no finite
  /// object depth in their 3 x 3 neighbourhood); they are left out of the gradient.
  int skippedBoundaryPixels() const { return skipped_boundary_pixels_; }

 private:
  OcclusionGradientOptions options_;
  std::unique_ptr<SmoothOcclusionLoss> loss_;  // rebuilt when the blur width changes
  cv::Mat others_smoothed_;                    // sum over j != k of S_j
  cv::Mat coarse_weight_;                      // G * (sum over j != k of S_j), coarse grid
  cv::Mat weight_;                             // the same at full resolution
  cv::Mat mask_du_, mask_dv_;                  // image gradient of M_k [1/px]
  int skipped_boundary_pixels_ = 0;
};

/// Central finite differences of L_s, re-rendering at azimuth +/- h and elevation +/- h (one-sided
/// at the elevation limit): four renders.
class FiniteDifferenceOcclusionGradient : public OcclusionGradient {
 public:
  explicit FiniteDifferenceOcclusionGradient(const OcclusionGradientOptions& options = {});

  GradientResult compute(RenderedView& view) override;
  std::string name() const override { return "finite_difference"; }

 private:
  OcclusionGradientOptions options_;
  std::unique_ptr<SmoothOcclusionLoss> loss_;
};

/// Throws InvalidArgumentError for a non-positive or non-finite step or a negative tolerance.
std::unique_ptr<OcclusionGradient> makeAnalyticGradient(
    const OcclusionGradientOptions& options = {});
std::unique_ptr<OcclusionGradient> makeFiniteDifferenceGradient(
    const OcclusionGradientOptions& options = {});
/// `method`: "analytic" | "finite_difference". Throws InvalidArgumentError otherwise.
std::unique_ptr<OcclusionGradient> makeOcclusionGradient(
    const std::string& method, const OcclusionGradientOptions& options = {});

}  // namespace occlusion_env
