// The oracle: the fewest fixed-length steps after which the camera can stand at an unoccluded
// view, and the first step of such a path. It reads the scene (it renders other poses), so it is
// a reference for every table and a label for training, never a competitor.
//
// A step moves the camera by exactly h = step_size in any direction of the (azimuth, elevation)
// plane (the environment's normalised actions; elevation clamped at its limit). So one step
// reaches exactly the circle of radius h, and k >= 2 steps reach every pose within k h: a target
// at distance d needs max(2, ceil(d / h)) steps (the last two steps bend to land on it exactly).
// The oracle searches the unoccluded poses on a lattice of spacing s anchored at the first pose
// it is asked about, nearest first, and the circle of radius h at 64 directions; the lattice's
// occlusion figures are cached for the scene. A lattice can miss an unoccluded region thinner
// than its spacing, so the answer is an upper bound of the true fewest steps: the training labels
// use s = h / 2, the `oracle` agent of the tables s = h / 4 (doc/ORACLE.md measures both).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "occlusion_env/agents/agent_registry.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {

struct OracleOptions {
  double lattice_spacing_steps = 0.5;  // s / h, in (0, 1]
  int circle_directions = 64;          // poses tried on the one-step circle
  int max_steps = 50;                  // search radius: no answer beyond max_steps * h

  /// Throws InvalidArgumentError naming the first option out of its declared range.
  void validate() const;
};

/// The declared options of OracleOptions (flag --spacing for the lattice spacing).
const OptionTable<OracleOptions>& oracleOptionTable();

struct OracleAnswer {
  /// Fewest steps to an unoccluded view; 0 when the pose is unoccluded; -1 when there is none
  /// within max_steps (a failure at the step limit).
  int steps = -1;
  /// The moves of one such path [rad]: steps entries of length h (empty for 0 and -1).
  std::vector<Action> path;
  SphericalPose target;    // where the path ends (unoccluded)
  int poses_rendered = 0;  // renders this query cost (cache misses)
  /// The first move's direction: atan2(d_elevation, d_azimuth) [rad] (doc/CONVENTIONS.md); NaN
  /// when there is no move.
  double firstDirectionRad() const;
};

class OcclusionOracle {
 public:
  /// Throws InvalidArgumentError for options out of range.
  explicit OcclusionOracle(Environment& environment, const OracleOptions& options = {});

  /// Forgets the cached occlusion: call when the environment shows a new scene. The lattice is
  /// then anchored at the next pose queried, or at `anchor`: answers depend only on the anchor
  /// and the pose (the cache only saves renders), so a fixed anchor makes them reproducible.
  void clear();
  void clear(const SphericalPose& anchor);

  /// The answer for `pose` in the environment's current scene (the episode is unchanged).
  OracleAnswer query(const SphericalPose& pose);

  /// Every first move that starts a path as short as `answer`'s (query(pose)'s), one entry per
  /// direction 2 pi k / circle_directions of the one-step circle (1: such a move); empty for 0 or
  /// -1 steps. One step: the directions that land on an unoccluded view. k >= 2 steps: those that
  /// land within (k - 1) h of an unoccluded lattice pose (for k = 2, within h: the landing pose's
  /// own circle is not rendered, so that is an estimate). The oracle's own first move lies in
  /// that set or at its edge (two steps: the bend is the edge of the arc of moves within h).
  /// Renders the lattice poses within k h that query() did not (about 12 (2k - 1) at s = h / 2).
  std::vector<std::uint8_t> shortestFirstMoves(const SphericalPose& pose,
                                               const OracleAnswer& answer);

 private:
  using LatticeIndex = std::pair<int, int>;
  std::int64_t occlusionAt(const SphericalPose& pose);
  std::int64_t occlusionAtLattice(const LatticeIndex& index);
  SphericalPose latticePose(const LatticeIndex& index) const;
  // `pose` in lattice units from the anchor (azimuth, elevation).
  Eigen::Vector2d latticeCoordinates(const SphericalPose& pose) const;
  // The offset [rad] from lattice coordinates `from` to the lattice point `index`.
  Eigen::Vector2d latticeOffset(const LatticeIndex& index, const Eigen::Vector2d& from) const;
  bool withinElevationLimits(const LatticeIndex& index) const;
  // Whether `pixels` of occlusion count as unoccluded (the environment's success threshold).
  bool solved(std::int64_t pixels) const;
  // The offset [rad] (azimuth, elevation) from `pose` to the nearest unoccluded lattice pose within
  // max_steps steps and the elevation limit; none when there is none.
  std::optional<Eigen::Vector2d> nearestUnoccludedLatticeOffset(const SphericalPose& pose);
  // The offsets [rad] from `pose` to every unoccluded lattice pose within `radius` [rad] and the
  // elevation limit.
  std::vector<Eigen::Vector2d> unoccludedLatticeOffsetsWithin(const SphericalPose& pose,
                                                              double radius);
  // Two steps from a clear view: the side of the heading to `target_offset` that the first move
  // bends to, +1 (counter-clockwise in the (azimuth, elevation) plane) or -1: the one whose
  // corner shows fewer occluded pixels (two renders).
  double twoStepSide(const SphericalPose& pose, const Eigen::Vector2d& target_offset,
                     double elevation_low, double elevation_high);
  // A single step from `pose` to an unoccluded view, its elevation change within
  // [elevation_low, elevation_high]: the middle of the widest run of the circle's directions
  // that give one; none when none does.
  std::optional<Action> unoccludingStep(const SphericalPose& pose, double elevation_low,
                                        double elevation_high);

  Environment& environment_;
  OracleOptions options_;
  double step_rad_;
  double spacing_rad_;
  bool anchored_ = false;
  SphericalPose anchor_;
  std::map<LatticeIndex, std::int64_t> cache_;
  std::vector<char> unoccluding_;             // per circle direction, unoccludingStep()'s
  std::optional<SphericalPose> circle_pose_;  // where unoccluding_ was found (none: nowhere yet)
  int renders_ = 0;
};

/// Follows the oracle's path, planned at its first act() of each episode (re-planned only if
/// the path runs out before the episode ends). Needs the in-process simulation.
class OracleAgent : public Agent {
 public:
  OracleAgent(Environment& environment, const OracleOptions& options = {});
  void reset(std::uint64_t seed) override;
  Action act(const RigObservation& observation) override;
  /// The plan of the current episode (its step count is the bound).
  const OracleAnswer& plan() const { return plan_; }

 private:
  OcclusionOracle oracle_;
  OracleAnswer plan_;
  std::size_t next_ = 0;
  bool planned_ = false;
};

/// The steps of the episode from `start` (the environment's current one) whose every move is the
/// oracle's first move from the current view turned by an angle ~ N(0, error_sd_rad) drawn from
/// `seed` (max_steps when it ends truncated): what an agent needs whose escape direction errs by
/// that much. Where the oracle finds nothing within reach the move is +azimuth, turned alike.
int followOracleWithError(Environment& environment, OcclusionOracle& oracle, StepResult start,
                          double error_sd_rad, std::uint64_t seed);

AgentEntry oracleAgentEntry();

}  // namespace occlusion_env
