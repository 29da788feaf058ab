#include "occlusion_env/geometry/camera.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

CameraIntrinsics CameraIntrinsics::fromFieldOfView(int width, int height,
                                                   double horizontal_fov_rad) {
  if (width < 16 || width > 4096 || height < 16 || height > 4096) {
    std::ostringstream message;
    message << "image size " << width << "x" << height << " is outside [16, 4096]";
    throw InvalidArgumentError(message.str());
  }
  if (!(horizontal_fov_rad > 0.0 && horizontal_fov_rad < M_PI)) {
    throw InvalidArgumentError("field of view must lie in (0, pi) rad, got " +
                               std::to_string(horizontal_fov_rad));
  }
  CameraIntrinsics intrinsics;
  intrinsics.width = width;
  intrinsics.height = height;
  // The image spans `width` pixels of unit size, edge to edge.
  intrinsics.fx = 0.5 * width / std::tan(0.5 * horizontal_fov_rad);
  intrinsics.fy = intrinsics.fx;
  intrinsics.cx = 0.5 * (width - 1);
  intrinsics.cy = 0.5 * (height - 1);
  return intrinsics;
}

SphericalCamera::SphericalCamera(double radius_m, double elevation_limit_rad)
    : SphericalCamera(radius_m, -elevation_limit_rad, elevation_limit_rad) {}

SphericalCamera::SphericalCamera(double radius_m, double lowest_elevation_rad,
                                 double highest_elevation_rad)
    : radius_m_(radius_m),
      lowest_elevation_rad_(lowest_elevation_rad),
      highest_elevation_rad_(highest_elevation_rad) {
  if (!(std::isfinite(radius_m) && radius_m > 0.0)) {
    throw InvalidArgumentError("camera radius must be a positive number of metres, got " +
                               std::to_string(radius_m));
  }
  if (!(lowest_elevation_rad > -0.5 * M_PI && lowest_elevation_rad <= highest_elevation_rad &&
        highest_elevation_rad < 0.5 * M_PI)) {
    throw InvalidArgumentError(
        "elevation range must satisfy -pi/2 < lowest <= highest < pi/2, got [" +
        std::to_string(lowest_elevation_rad) + ", " + std::to_string(highest_elevation_rad) +
        "] rad");
  }
}

double azimuthChange(const SphericalPose& from, const SphericalPose& to) {
  return std::remainder(to.azimuth_rad - from.azimuth_rad, 2.0 * M_PI);
}

SphericalPose SphericalCamera::normalized(const SphericalPose& pose) const {
  SphericalPose out;
  // Wrap to (-pi, pi].
  out.azimuth_rad = std::remainder(pose.azimuth_rad, 2.0 * M_PI);
  if (out.azimuth_rad <= -M_PI) out.azimuth_rad += 2.0 * M_PI;
  out.elevation_rad = std::clamp(pose.elevation_rad, lowest_elevation_rad_, highest_elevation_rad_);
  return out;
}

SphericalPose SphericalCamera::moved(const SphericalPose& pose, double d_azimuth_rad,
                                     double d_elevation_rad) const {
  return normalized({pose.azimuth_rad + d_azimuth_rad, pose.elevation_rad + d_elevation_rad});
}

Eigen::Vector3d SphericalCamera::position(const SphericalPose& pose) const {
  const double ce = std::cos(pose.elevation_rad);
  return radius_m_ * Eigen::Vector3d(ce * std::cos(pose.azimuth_rad),
                                     ce * std::sin(pose.azimuth_rad), std::sin(pose.elevation_rad));
}

Eigen::Isometry3d SphericalCamera::worldFromBody(const SphericalPose& pose) const {
  const double ca = std::cos(pose.azimuth_rad), sa = std::sin(pose.azimuth_rad);
  const double ce = std::cos(pose.elevation_rad), se = std::sin(pose.elevation_rad);
  // Closed form, well defined everywhere within the elevation limit.
  const Eigen::Vector3d forward(-ce * ca, -ce * sa, -se);  // towards the origin
  const Eigen::Vector3d left(sa, -ca, 0.0);                // up x forward
  const Eigen::Vector3d up = forward.cross(left);
  Eigen::Isometry3d world_from_body = Eigen::Isometry3d::Identity();
  world_from_body.linear().col(0) = forward;
  world_from_body.linear().col(1) = left;
  world_from_body.linear().col(2) = up;
  world_from_body.translation() = position(pose);
  return world_from_body;
}

Eigen::Isometry3d SphericalCamera::worldFromOptical(const SphericalPose& pose) const {
  Eigen::Isometry3d world_from_optical = worldFromBody(pose);
  world_from_optical.linear() = world_from_optical.linear() * bodyFromOpticalRotation();
  return world_from_optical;
}

Eigen::Matrix3d bodyFromOpticalRotation() {
  // Columns: the optical x (right), y (down), z (forward) axes in the body frame.
  Eigen::Matrix3d body_from_optical;
  body_from_optical << 0, 0, 1,  //
      -1, 0, 0,                  //
      0, -1, 0;
  return body_from_optical;
}

SphericalPose sphericalPoseOf(const Eigen::Vector3d& position_m) {
  return {std::atan2(position_m.y(), position_m.x()),
          std::atan2(position_m.z(), std::hypot(position_m.x(), position_m.y()))};
}

}  // namespace occlusion_env
