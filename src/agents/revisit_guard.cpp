#include "occlusion_env/agents/revisit_guard.hpp"

#include <cmath>

namespace occlusion_env {

void RevisitGuard::observe(const RigObservation& observation) {
  if (observation.step_index == 0 || known_poses_ == 0) {
    known_poses_ = 1;
    poses_[0] = observation.pose;
    step_length_rad_ = 0.0;
    last_azimuth_sign_ = 1.0;
    return;
  }
  const double moved_azimuth = azimuthChange(poses_[0], observation.pose);
  const double moved_elevation = observation.pose.elevation_rad - poses_[0].elevation_rad;
  const double length = std::hypot(moved_azimuth, moved_elevation);
  if (length > 0.0) step_length_rad_ = length;
  if (observation.last_action.d_azimuth_rad != 0.0) {
    last_azimuth_sign_ = observation.last_action.d_azimuth_rad < 0.0 ? -1.0 : 1.0;
  }
  for (int k = kRememberedPoses - 1; k > 0; --k) poses_[k] = poses_[k - 1];
  poses_[0] = observation.pose;
  if (known_poses_ < kRememberedPoses) ++known_poses_;
}

bool RevisitGuard::landsOnARecentView(const Action& unit_direction) const {
  const SphericalPose landing{
      poses_[0].azimuth_rad + step_length_rad_ * unit_direction.d_azimuth_rad,
      poses_[0].elevation_rad + step_length_rad_ * unit_direction.d_elevation_rad};
  for (int k = 1; k < known_poses_; ++k) {
    const double distance = std::hypot(azimuthChange(poses_[k], landing),
                                       landing.elevation_rad - poses_[k].elevation_rad);
    if (distance < 0.5 * step_length_rad_) return true;
  }
  return false;
}

Action RevisitGuard::awayFromRecentViews(const Action& direction) const {
  const double length = std::hypot(direction.d_azimuth_rad, direction.d_elevation_rad);
  if (step_length_rad_ == 0.0 || known_poses_ < 2 || length == 0.0) return direction;
  const Action unit{direction.d_azimuth_rad / length, direction.d_elevation_rad / length};
  if (!landsOnARecentView(unit)) return direction;
  for (const double turn : {M_PI / 4.0, M_PI / 2.0, 3.0 * M_PI / 4.0}) {
    for (const double side : {last_azimuth_sign_, -last_azimuth_sign_}) {
      const double c = std::cos(side * turn), s = std::sin(side * turn);
      const Action turned{c * unit.d_azimuth_rad - s * unit.d_elevation_rad,
                          s * unit.d_azimuth_rad + c * unit.d_elevation_rad};
      if (!landsOnARecentView(turned)) {
        return {length * turned.d_azimuth_rad, length * turned.d_elevation_rad};
      }
    }
  }
  return direction;
}

}  // namespace occlusion_env
