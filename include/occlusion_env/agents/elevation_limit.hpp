// What an agent can tell from the rig alone: that its last move was stopped at an elevation limit
// (a floor below the camera, the top of the rig's reach). A rig clamps the elevation of a move
// and keeps its azimuth (geometry/camera.hpp), so a move that asked to descend and did not, or
// descended less than its azimuth change says it should have, hit the lowest elevation.
#pragma once

#include "occlusion_env/env/environment_interface.hpp"

namespace occlusion_env {

/// Follows the rig's pose and moves over an episode and says which way the elevation is blocked.
/// Only the pose and the move as asked are read: no scene, no limit given.
class ElevationLimitTracker {
 public:
  /// -1: the last move asked to descend and the rig stopped it (the camera stands at its lowest
  /// elevation); +1: the same upwards; 0: neither. A block stays until the rig moves the other
  /// way, since moving along the limit does not leave it. A move that asked for elevation only
  /// and was shortened, not stopped, is noticed at the next one (nothing says how long it was).
  int blockedDirection() const { return blocked_direction_; }

  /// Reads the observation of a step (or of a reset, step_index 0, which forgets the episode).
  void observe(const RigObservation& observation);

  /// `direction` (d_azimuth, d_elevation) turned along the limit where it points the blocked
  /// way: all of its length in azimuth, on the side the rig already goes along it (so that it
  /// does not swing back and forth), else on the side of its azimuth part (of the last move's
  /// where it had none). Unchanged when nothing is blocked or it points away from the limit.
  Action alongTheLimit(const Action& direction) const;

 private:
  bool has_previous_ = false;
  SphericalPose previous_pose_;
  int blocked_direction_ = 0;
  int along_sign_ = 0;  // the azimuth's sign of the moves along the limit so far; 0 before one
  int last_azimuth_sign_ = 1;  // of the last move asked for (+1 after a reset or without one)
};

}  // namespace occlusion_env
