// The surfaces that bound a view, found in its depth: large planes (a floor, a wall) with nothing
// seen behind them. Occlusion is where one object's silhouette overlaps another's, so a pixel
// that shows a bare floor or wall is never occluded; an estimate of occlusion there (a network
// that takes a floor seen from above for objects) is wrong by construction. A large flat face
// of an object is not such a surface: whatever it hides is seen beside it, behind its plane.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "occlusion_env/geometry/camera.hpp"

namespace occlusion_env {

struct BoundingSurfaceOptions {
  // A plane counts when it holds at least this fraction of the image's pixels.
  double min_support = 0.15;
  // A point lies on a plane within tolerance_m + tolerance_per_m2 * z^2 [m] (z: its depth [m];
  // a stereo camera's error grows with z^2).
  double tolerance_m = 0.02;
  double tolerance_per_m2 = 0.004;
  // At most this fraction of the view's valid points may lie behind a bounding plane (farther
  // than the tolerance on the side away from the camera).
  double max_behind = 0.02;
  int max_planes = 3;      // a floor and two walls
  int iterations = 200;    // RANSAC draws per plane
  std::uint64_t seed = 1;  // the draws' seed: the same depth gives the same planes

  /// Throws InvalidArgumentError for values outside their ranges.
  void validate() const;
};

/// A plane n . p + d = 0 in the optical frame (n unit, pointing towards the camera: d > 0).
struct SurfacePlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset_m = 0.0;
  int support_px = 0;
};

/// Finds the bounding surfaces of `depth` (CV_32FC1 [m], NaN = no reading) seen with
/// `intrinsics` (of depth's size), and writes `on_surface` (CV_8UC1 at depth's size, 255 on a
/// bounding surface, else 0; reused). Returns the planes found, largest first. Deterministic.
/// Allocation-free once `on_surface` and the scratch are sized.
class BoundingSurfaceFinder {
 public:
  explicit BoundingSurfaceFinder(const BoundingSurfaceOptions& options = {});

  const std::vector<SurfacePlane>& find(const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                                        cv::Mat& on_surface);

  const BoundingSurfaceOptions& options() const { return options_; }

 private:
  BoundingSurfaceOptions options_;
  std::vector<Eigen::Vector3d> points_;  // the valid pixels' points, optical frame [m]
  std::vector<int> pixel_of_point_;      // row * width + col of each point
  std::vector<int> free_;                // indices of points not yet on a plane
  std::vector<int> inliers_, best_inliers_;
  std::vector<SurfacePlane> planes_;
};

}  // namespace occlusion_env
