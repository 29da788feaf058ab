// What an agent remembers of its own path: the last few poses of the rig. An agent that follows
// a direction read from one image can swing between two views, each pointing at the other
// (doc/AGENTS.md); this turns a move that would land back on a recent view aside.
#pragma once

#include <array>

#include "occlusion_env/env/environment_interface.hpp"

namespace occlusion_env {

class RevisitGuard {
 public:
  /// Reads the observation of a step (or of a reset, step_index 0, which forgets the path).
  void observe(const RigObservation& observation);

  /// `direction` (d_azimuth, d_elevation), or, where a move along it of the rig's step length
  /// (the length of its last move) would land within half a step of one of the last
  /// kRememberedPoses poses, the smallest turn of it (45, 90, 135 deg, to one side, then the
  /// other) that does not. Unchanged before the first move, or when every turn lands on a
  /// recent view.
  Action awayFromRecentViews(const Action& direction) const;

  static constexpr int kRememberedPoses = 4;  // the current pose and the 3 before it

 private:
  bool landsOnARecentView(const Action& unit_direction) const;

  std::array<SphericalPose, kRememberedPoses> poses_{};  // poses_[0] the current one
  int known_poses_ = 0;
  double step_length_rad_ = 0.0;  // of the last move, in (azimuth, elevation) [rad]
  double last_azimuth_sign_ = 1.0;
};

}  // namespace occlusion_env
