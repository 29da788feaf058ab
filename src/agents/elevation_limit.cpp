#include "occlusion_env/agents/elevation_limit.hpp"

#include <cmath>

namespace occlusion_env {
namespace {

// A move counts as stopped when it covered less than this share of the elevation it asked for
// (the azimuth says how far it went). Loose: a real rig arrives within a tolerance.
constexpr double kStoppedShare = 0.5;
// [rad] below this the rig did not move in elevation at all (a move that asked for elevation only).
constexpr double kNoMoveRad = 1e-4;

}  // namespace

void ElevationLimitTracker::observe(const RigObservation& observation) {
  if (observation.step_index == 0 || !has_previous_) {
    blocked_direction_ = 0;
    along_sign_ = 0;
    last_azimuth_sign_ = 1;
    has_previous_ = true;
    previous_pose_ = observation.pose;
    return;
  }
  const Action& asked = observation.last_action;
  const double moved_azimuth = azimuthChange(previous_pose_, observation.pose);
  const double moved_elevation = observation.pose.elevation_rad - previous_pose_.elevation_rad;
  previous_pose_ = observation.pose;
  last_azimuth_sign_ = asked.d_azimuth_rad < 0.0 ? -1 : 1;
  const double asked_length = std::hypot(asked.d_azimuth_rad, asked.d_elevation_rad);
  if (asked_length == 0.0) return;
  const int asked_direction = asked.d_elevation_rad > 0.0   ? 1
                              : asked.d_elevation_rad < 0.0 ? -1
                                                            : 0;
  // A move the other way leaves the limit it stood at.
  if (blocked_direction_ != 0 && moved_elevation * blocked_direction_ < -kNoMoveRad) {
    blocked_direction_ = 0;
    along_sign_ = 0;
  }
  // The side it went along the limit, kept while the limit holds it.
  if (blocked_direction_ != 0 && asked.d_elevation_rad == 0.0) {
    along_sign_ = asked.d_azimuth_rad < 0.0 ? -1 : 1;
  }
  if (asked_direction == 0) return;
  double expected_elevation;  // [rad] what the move would have covered in elevation, unclamped
  if (std::abs(asked.d_azimuth_rad) > 0.05 * asked_length) {
    expected_elevation = asked.d_elevation_rad * (moved_azimuth / asked.d_azimuth_rad);
  } else {
    expected_elevation = asked_direction * kNoMoveRad / kStoppedShare;  // any move at all
  }
  if (expected_elevation * asked_direction <= 0.0) return;  // the azimuth went the other way
  if (moved_elevation * asked_direction < kStoppedShare * std::abs(expected_elevation)) {
    blocked_direction_ = asked_direction;
  }
}

Action ElevationLimitTracker::alongTheLimit(const Action& direction) const {
  if (blocked_direction_ == 0 || direction.d_elevation_rad * blocked_direction_ <= 0.0) {
    return direction;
  }
  const double length = std::hypot(direction.d_azimuth_rad, direction.d_elevation_rad);
  Action along;
  along.d_elevation_rad = 0.0;
  double sign = last_azimuth_sign_;
  if (along_sign_ != 0) {
    sign = along_sign_;
  } else if (std::abs(direction.d_azimuth_rad) > 1e-3 * length) {
    sign = direction.d_azimuth_rad;
  }
  along.d_azimuth_rad = sign < 0.0 ? -length : length;  // the whole move, along the limit
  return along;
}

}  // namespace occlusion_env
