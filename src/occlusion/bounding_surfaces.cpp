#include "occlusion_env/occlusion/bounding_surfaces.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <string>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/random.hpp"

namespace occlusion_env {
namespace {

constexpr std::size_t kScoredPoints = 1024;

double tolerance(const BoundingSurfaceOptions& options, double z_m) {
  return options.tolerance_m + options.tolerance_per_m2 * z_m * z_m;
}

// The plane with unit normal `normal` through `point`, its normal turned towards the camera (the
// origin).
SurfacePlane facingCamera(const Eigen::Vector3d& normal, const Eigen::Vector3d& point) {
  SurfacePlane plane;
  const double offset = -normal.dot(point);
  plane.normal = offset < 0.0 ? Eigen::Vector3d(-normal) : normal;
  plane.offset_m = std::abs(offset);
  return plane;
}

// The plane through three points, facing the camera (the origin); false when they are collinear.
bool planeThrough(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  SurfacePlane& plane) {
  const Eigen::Vector3d normal = (b - a).cross(c - a);
  const double length = normal.norm();
  if (!(length > 1e-9)) return false;
  plane = facingCamera(normal / length, a);
  return true;
}

// The least-squares plane through `points[indices]`, facing the camera; false when degenerate.
bool fitPlane(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& indices,
              SurfacePlane& plane) {
  if (indices.size() < 3) return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i : indices) mean += points[i];
  mean /= static_cast<double>(indices.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int i : indices) {
    const Eigen::Vector3d d = points[i] - mean;
    scatter += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  if (solver.info() != Eigen::Success) return false;
  plane = facingCamera(solver.eigenvectors().col(0), mean);  // the smallest eigenvalue's
  return true;
}

}  // namespace

void BoundingSurfaceOptions::validate() const {
  const auto require = [](bool ok, const std::string& what) {
    if (!ok) throw InvalidArgumentError("bounding surfaces: " + what);
  };
  require(min_support > 0.0 && min_support <= 1.0, "min_support must lie in (0, 1]");
  require(tolerance_m >= 0.0 && tolerance_per_m2 >= 0.0 && tolerance_m + tolerance_per_m2 > 0.0,
          "the tolerances must be >= 0 and not both 0");
  require(max_behind >= 0.0 && max_behind < 1.0, "max_behind must lie in [0, 1)");
  require(max_planes >= 1 && max_planes <= 8, "max_planes must lie in [1, 8]");
  require(iterations >= 1 && iterations <= 100000, "iterations must lie in [1, 100000]");
}

BoundingSurfaceFinder::BoundingSurfaceFinder(const BoundingSurfaceOptions& options)
    : options_(options) {
  options_.validate();
}

const std::vector<SurfacePlane>& BoundingSurfaceFinder::find(const cv::Mat& depth,
                                                             const CameraIntrinsics& intrinsics,
                                                             cv::Mat& on_surface) {
  if (depth.type() != CV_32FC1) throw InvalidArgumentError("bounding surfaces: depth not 32FC1");
  if (!(intrinsics.fx > 0.0 && intrinsics.fy > 0.0)) {
    throw InvalidArgumentError("bounding surfaces: focal lengths must be positive");
  }
  on_surface.create(depth.size(), CV_8UC1);
  on_surface.setTo(0);
  planes_.clear();
  points_.clear();
  pixel_of_point_.clear();
  for (int row = 0; row < depth.rows; ++row) {
    const float* z = depth.ptr<float>(row);
    for (int col = 0; col < depth.cols; ++col) {
      if (!(z[col] > 0.0f && std::isfinite(z[col]))) continue;
      const double zm = z[col];
      points_.emplace_back((col - intrinsics.cx) * zm / intrinsics.fx,
                           (row - intrinsics.cy) * zm / intrinsics.fy, zm);
      pixel_of_point_.push_back(row * depth.cols + col);
    }
  }
  const int total = static_cast<int>(points_.size());
  const int min_support =
      static_cast<int>(std::ceil(options_.min_support * static_cast<double>(depth.total())));
  const int max_behind = static_cast<int>(options_.max_behind * total);
  free_.resize(total);
  for (int i = 0; i < total; ++i) free_[i] = i;

  const auto collect = [this](const SurfacePlane& plane, std::vector<int>& inliers) {
    inliers.clear();
    for (int i : free_) {
      const Eigen::Vector3d& p = points_[i];
      if (std::abs(plane.normal.dot(p) + plane.offset_m) <= tolerance(options_, p.z())) {
        inliers.push_back(i);
      }
    }
  };
  // Points farther than the tolerance on the plane's far side (all of them, on planes or not).
  const auto behind = [this, max_behind](const SurfacePlane& plane) {
    int count = 0;
    for (const Eigen::Vector3d& p : points_) {
      if (plane.normal.dot(p) + plane.offset_m < -tolerance(options_, p.z()) &&
          ++count > max_behind) {
        break;
      }
    }
    return count;
  };

  // The largest plane left first. One that is not a bounding surface (an object's face, a table
  // top with chairs seen beyond it) is set aside, and the search goes on among the other points.
  RandomSource random(options_.seed);
  for (int attempt = 0; attempt < 2 * options_.max_planes &&
                        static_cast<int>(planes_.size()) < options_.max_planes &&
                        static_cast<int>(free_.size()) >= min_support;
       ++attempt) {
    const auto count = static_cast<std::uint64_t>(free_.size());
    // Candidates are scored on every stride-th free point (about kScoredPoints of them).
    const std::size_t stride = std::max<std::size_t>(1, free_.size() / kScoredPoints);
    SurfacePlane best;
    int best_score = -1;
    for (int draw = 0; draw < options_.iterations; ++draw) {
      SurfacePlane candidate;
      if (!planeThrough(points_[free_[random.below(count)]], points_[free_[random.below(count)]],
                        points_[free_[random.below(count)]], candidate)) {
        continue;
      }
      int score = 0;
      for (std::size_t k = 0; k < free_.size(); k += stride) {
        const Eigen::Vector3d& p = points_[free_[k]];
        score +=
            std::abs(candidate.normal.dot(p) + candidate.offset_m) <= tolerance(options_, p.z());
      }
      if (score > best_score) {
        best = candidate;
        best_score = score;
      }
    }
    if (best_score < 0) break;
    collect(best, best_inliers_);
    if (static_cast<int>(best_inliers_.size()) < min_support) break;
    // One least-squares refinement on the inliers; kept only if it holds as many.
    SurfacePlane refined;
    if (fitPlane(points_, best_inliers_, refined)) {
      collect(refined, inliers_);
      if (inliers_.size() >= best_inliers_.size()) {
        best = refined;
        best_inliers_.swap(inliers_);
      }
    }
    if (behind(best) <= max_behind) {
      best.support_px = static_cast<int>(best_inliers_.size());
      planes_.push_back(best);
      std::uint8_t* mask = on_surface.ptr<std::uint8_t>(0);
      for (int i : best_inliers_) mask[pixel_of_point_[i]] = 255;
    }
    // Either way its points are done with: erase them (both lists are in ascending order).
    std::size_t kept = 0, next_inlier = 0;
    for (int i : free_) {
      if (next_inlier < best_inliers_.size() && best_inliers_[next_inlier] == i) {
        ++next_inlier;
      } else {
        free_[kept++] = i;
      }
    }
    free_.resize(kept);
  }
  return planes_;
}

}  // namespace occlusion_env
