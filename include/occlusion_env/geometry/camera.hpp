// The camera: a pinhole on a sphere around the scene centre, always looking at it.
// Conventions (written down once, in doc/CONVENTIONS.md):
//  - world frame: REP 103, x forward, y left, z up; metres; the scene centre is the origin.
//  - azimuth: angle about world +z from +x towards +y [rad], wrapped to (-pi, pi].
//  - elevation: angle above the horizontal xy plane [rad], clamped to [lowest, highest]
//    (+/- the elevation limit unless something, e.g. a room's floor, sets a higher lowest).
//  - position = radius * (cos(el) cos(az), cos(el) sin(az), sin(el)).
//  - optical frame (REP 103 camera convention): z forward (towards the origin), x right, y down.
#pragma once

#include <Eigen/Geometry>

namespace occlusion_env {

/// Camera angles on the sphere [rad].
struct SphericalPose {
  double azimuth_rad = 0.0;
  double elevation_rad = 0.0;
};

/// The azimuth from `from` to `to` the short way round, in [-pi, pi] [rad].
double azimuthChange(const SphericalPose& from, const SphericalPose& to);

/// Pinhole intrinsics in ROS's convention: pixel centres at integer coordinates, so the principal
/// point of a W x H image is ((W - 1) / 2, (H - 1) / 2).
struct CameraIntrinsics {
  int width = 256;
  int height = 256;
  double fx = 0.0;  // [px]
  double fy = 0.0;  // [px]
  double cx = 0.0;  // [px]
  double cy = 0.0;  // [px]

  /// Square pixels; `horizontal_fov_rad` spans the image width. Throws InvalidArgumentError for a
  /// size outside [16, 4096] or a field of view outside (0, pi).
  static CameraIntrinsics fromFieldOfView(int width, int height, double horizontal_fov_rad);

  /// Projects a point given in the optical frame to pixel coordinates (no bounds check).
  Eigen::Vector2d project(const Eigen::Vector3d& point_optical) const {
    return {fx * point_optical.x() / point_optical.z() + cx,
            fy * point_optical.y() / point_optical.z() + cy};
  }
};

class SphericalCamera {
 public:
  /// Elevation within +/- `elevation_limit_rad`. Throws InvalidArgumentError unless radius > 0
  /// and 0 <= elevation limit < pi/2.
  SphericalCamera(double radius_m, double elevation_limit_rad);
  /// Elevation within [lowest, highest]. Throws InvalidArgumentError unless radius > 0 and
  /// -pi/2 < lowest <= highest < pi/2.
  SphericalCamera(double radius_m, double lowest_elevation_rad, double highest_elevation_rad);

  double radius() const { return radius_m_; }
  double lowestElevation() const { return lowest_elevation_rad_; }
  double highestElevation() const { return highest_elevation_rad_; }

  /// Azimuth wrapped to (-pi, pi], elevation clamped to [lowest, highest].
  SphericalPose normalized(const SphericalPose& pose) const;

  /// `pose` moved by the given angle increments, then normalized.
  SphericalPose moved(const SphericalPose& pose, double d_azimuth_rad,
                      double d_elevation_rad) const;

  /// Camera centre in the world frame [m].
  Eigen::Vector3d position(const SphericalPose& pose) const;

  /// Camera body frame (x forward towards the origin, y left, z up) in the world frame.
  Eigen::Isometry3d worldFromBody(const SphericalPose& pose) const;

  /// Optical frame (z forward, x right, y down) in the world frame.
  Eigen::Isometry3d worldFromOptical(const SphericalPose& pose) const;

 private:
  double radius_m_;
  double lowest_elevation_rad_;   // [rad]
  double highest_elevation_rad_;  // [rad]
};

/// The azimuth and elevation of `position_m` seen from the sphere's centre (doc/CONVENTIONS.md),
/// neither wrapped nor clamped beyond atan2's ranges; its distance is ignored. For a camera whose
/// pose is measured (tf) rather than set. The origin gives (0, 0).
SphericalPose sphericalPoseOf(const Eigen::Vector3d& position_m);

/// The fixed rotation from the camera body frame to its optical frame (REP 103).
Eigen::Matrix3d bodyFromOpticalRotation();

}  // namespace occlusion_env
