#include "occlusion_env/agents/oracle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <random>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/occlusion/occlusion.hpp"

namespace occlusion_env {
namespace {

Action move(double direction_rad, double length) {
  return {length * std::cos(direction_rad), length * std::sin(direction_rad)};
}

// Steps needed to land exactly on a target at distance d (> 0) with moves of length h.
int stepsFor(double distance, double h) {
  return std::max(2, static_cast<int>(std::ceil(distance / h - 1e-9)));
}

// The angle [rad] between the heading to a target `remaining` away (in (0, 2h]) and each of the
// two moves of length h that land on it.
double bendFor(double remaining, double h) {
  return std::acos(std::clamp(remaining / (2.0 * h), -1.0, 1.0));
}

// The moves from the origin to `offset` (length d > 0) in `steps` moves of length h: straight
// towards the target, the last two bending so that they land on it. The bend counter-clockwise
// of the heading (+1) or clockwise (-1): `preferred_side` when its corner lies within the allowed
// elevation offsets [elevation_low, elevation_high], else the other.
std::vector<Action> pathTo(const Eigen::Vector2d& offset, int steps, double h, double elevation_low,
                           double elevation_high, double preferred_side = 1.0) {
  const double distance = offset.norm();
  const double heading = std::atan2(offset.y(), offset.x());
  std::vector<Action> path;  // steps >= 2: one step is the circle's case
  for (int i = 0; i < steps - 2; ++i) path.push_back(move(heading, h));
  const double bend = bendFor(distance - (steps - 2) * h, h);
  const Eigen::Vector2d before = offset.normalized() * ((steps - 2) * h);
  for (const double sign : {preferred_side, -preferred_side}) {
    const double first = heading + sign * bend;
    const double corner_elevation = before.y() + h * std::sin(first);
    if (sign != preferred_side ||
        (corner_elevation >= elevation_low && corner_elevation <= elevation_high)) {
      path.push_back(move(first, h));
      path.push_back(move(heading - sign * bend, h));
      break;
    }
  }
  return path;
}

}  // namespace

double OracleAnswer::firstDirectionRad() const {
  if (path.empty()) return std::numeric_limits<double>::quiet_NaN();
  return std::atan2(path.front().d_elevation_rad, path.front().d_azimuth_rad);
}

const OptionTable<OracleOptions>& oracleOptionTable() {
  static const auto table =
      OptionTable<OracleOptions>()
          .add("lattice_spacing_steps", &OracleOptions::lattice_spacing_steps,
               OptionSpec("lattice spacing in steps (finer: closer to the true fewest steps, "
                          "slower)")
                   .above(0)
                   .atMost(1)
                   .flag("--spacing"))
          .add("circle_directions", &OracleOptions::circle_directions,
               OptionSpec("poses tried on the one-step circle").range(4, 4096))
          .add("max_steps", &OracleOptions::max_steps,
               OptionSpec("search radius: no answer beyond this many steps").atLeast(1));
  return table;
}

void OracleOptions::validate() const {
  oracleOptionTable().check(*this);
}

OcclusionOracle::OcclusionOracle(Environment& environment, const OracleOptions& options)
    : environment_(environment),
      options_(options),
      step_rad_(environment.options().step_size_rad),
      spacing_rad_(options.lattice_spacing_steps * step_rad_) {
  options.validate();
  if (!environment.options().normalize_action) {
    throw InvalidArgumentError("oracle: the environment must normalise actions (fixed steps)");
  }
}

void OcclusionOracle::clear() {
  cache_.clear();
  circle_pose_.reset();
  anchored_ = false;
}

void OcclusionOracle::clear(const SphericalPose& anchor) {
  cache_.clear();
  circle_pose_.reset();
  anchor_ = anchor;
  anchored_ = true;
}

std::int64_t OcclusionOracle::occlusionAt(const SphericalPose& pose) {
  ++renders_;
  const RenderBuffers& buffers = environment_.renderAt(pose);
  return computeOcclusion(buffers.amodal_bits, environment_.numObjects(), buffers.target_footprint)
      .total_pixels;
}

SphericalPose OcclusionOracle::latticePose(const LatticeIndex& index) const {
  return {anchor_.azimuth_rad + index.first * spacing_rad_,
          anchor_.elevation_rad + index.second * spacing_rad_};
}

Eigen::Vector2d OcclusionOracle::latticeCoordinates(const SphericalPose& pose) const {
  return {azimuthChange(anchor_, pose) / spacing_rad_,
          (pose.elevation_rad - anchor_.elevation_rad) / spacing_rad_};
}

Eigen::Vector2d OcclusionOracle::latticeOffset(const LatticeIndex& index,
                                               const Eigen::Vector2d& from) const {
  return {(index.first - from.x()) * spacing_rad_, (index.second - from.y()) * spacing_rad_};
}

bool OcclusionOracle::withinElevationLimits(const LatticeIndex& index) const {
  const SphericalCamera& camera = environment_.camera();
  const double elevation = latticePose(index).elevation_rad;
  return elevation >= camera.lowestElevation() && elevation <= camera.highestElevation();
}

std::int64_t OcclusionOracle::occlusionAtLattice(const LatticeIndex& index) {
  const auto found = cache_.find(index);
  if (found != cache_.end()) return found->second;
  const std::int64_t pixels = occlusionAt(latticePose(index));
  cache_.emplace(index, pixels);
  return pixels;
}

bool OcclusionOracle::solved(std::int64_t pixels) const {
  return pixels <= static_cast<double>(environment_.options().reward.success_threshold_pixels);
}

std::optional<Eigen::Vector2d> OcclusionOracle::nearestUnoccludedLatticeOffset(
    const SphericalPose& pose) {
  // Lattice points in order of their distance from `pose`. Points in Chebyshev ring r around the
  // nearest lattice point lie at least (r - 0.5) s away, so once ring r is queued every point
  // nearer than (r + 0.5) s is known.
  const Eigen::Vector2d at = latticeCoordinates(pose);
  const int center_a = static_cast<int>(std::lround(at.x()));
  const int center_e = static_cast<int>(std::lround(at.y()));
  const double max_distance = options_.max_steps * step_rad_;
  const int max_ring = static_cast<int>(std::ceil(max_distance / spacing_rad_)) + 1;
  using Candidate = std::pair<double, LatticeIndex>;  // distance [rad], index
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> queue;
  const auto offsetOf = [&](const LatticeIndex& index) { return latticeOffset(index, at); };
  const auto push = [&](int a, int e) {
    const LatticeIndex index{a, e};
    if (!withinElevationLimits(index)) return;
    const double distance = offsetOf(index).norm();
    if (distance > 0.0 && distance <= max_distance + 1e-12) queue.push({distance, index});
  };
  for (int ring = 0; ring <= max_ring; ++ring) {
    if (ring == 0) {
      push(center_a, center_e);
    } else {
      for (int i = -ring; i <= ring; ++i) {
        push(center_a + i, center_e - ring);
        push(center_a + i, center_e + ring);
        if (i != -ring && i != ring) {
          push(center_a - ring, center_e + i);
          push(center_a + ring, center_e + i);
        }
      }
    }
    const double known =
        ring == max_ring ? std::numeric_limits<double>::infinity() : (ring + 0.5) * spacing_rad_;
    while (!queue.empty() && queue.top().first <= known) {
      const LatticeIndex index = queue.top().second;
      queue.pop();
      if (solved(occlusionAtLattice(index))) return offsetOf(index);
    }
  }
  return std::nullopt;
}

std::vector<Eigen::Vector2d> OcclusionOracle::unoccludedLatticeOffsetsWithin(
    const SphericalPose& pose, double radius) {
  const Eigen::Vector2d at = latticeCoordinates(pose);
  const double span = radius / spacing_rad_;
  std::vector<Eigen::Vector2d> offsets;
  for (int a = static_cast<int>(std::floor(at.x() - span));
       a <= static_cast<int>(std::ceil(at.x() + span)); ++a) {
    for (int e = static_cast<int>(std::floor(at.y() - span));
         e <= static_cast<int>(std::ceil(at.y() + span)); ++e) {
      const LatticeIndex index{a, e};
      if (!withinElevationLimits(index)) continue;
      const Eigen::Vector2d offset = latticeOffset(index, at);
      if (offset.norm() > radius + 1e-12) continue;
      if (solved(occlusionAtLattice(index))) offsets.push_back(offset);
    }
  }
  return offsets;
}

std::optional<Action> OcclusionOracle::unoccludingStep(const SphericalPose& pose,
                                                       double elevation_low,
                                                       double elevation_high) {
  // Every direction of the circle is tried; the step taken is the middle one of the widest run
  // of neighbouring directions that all unocclude, so that a step a little off (an agent
  // imitating it) still lands in the clear. The first direction found would lie at the run's
  // edge, where most steps a few degrees off do not.
  const int directions = options_.circle_directions;
  unoccluding_.assign(static_cast<std::size_t>(directions), 0);
  circle_pose_ = pose;
  int found = 0;
  for (int k = 0; k < directions; ++k) {
    const Action step = move(2.0 * M_PI * k / directions, step_rad_);
    if (step.d_elevation_rad < elevation_low || step.d_elevation_rad > elevation_high) continue;
    const SphericalPose there{pose.azimuth_rad + step.d_azimuth_rad,
                              pose.elevation_rad + step.d_elevation_rad};
    if (solved(occlusionAt(there))) {
      unoccluding_[static_cast<std::size_t>(k)] = 1;
      ++found;
    }
  }
  if (found == 0) return std::nullopt;
  int middle = 0;  // the whole circle unoccludes: any direction does
  if (found < directions) {
    // Runs around the circle, starting after a direction that does not unocclude.
    int start = 0;
    while (unoccluding_[static_cast<std::size_t>(start)]) ++start;
    int best_length = 0, length = 0;
    for (int i = 1; i <= directions; ++i) {
      const int k = (start + i) % directions;
      if (unoccluding_[static_cast<std::size_t>(k)]) {
        if (++length > best_length) {
          best_length = length;
          middle = (k - (length - 1) / 2 + directions) % directions;
        }
      } else {
        length = 0;
      }
    }
  }
  return move(2.0 * M_PI * middle / directions, step_rad_);
}

double OcclusionOracle::twoStepSide(const SphericalPose& pose, const Eigen::Vector2d& target_offset,
                                    double elevation_low, double elevation_high) {
  // Two steps from a clear view the first move is the bend itself, up to 60 deg off the heading:
  // a fixed side (counter-clockwise) is mirrored by a training image's flip into a label the
  // oracle never gives, so the side is chosen by what the two corners show, which a mirrored
  // scene shows mirrored.
  const double heading = std::atan2(target_offset.y(), target_offset.x());
  const double bend = bendFor(target_offset.norm(), step_rad_);
  if (bend < 1e-9) return 1.0;  // one corner, straight ahead
  std::int64_t pixels[2];
  for (const int i : {0, 1}) {
    const Action first = move(heading + (i == 0 ? bend : -bend), step_rad_);
    if (first.d_elevation_rad < elevation_low || first.d_elevation_rad > elevation_high) {
      return i == 0 ? -1.0 : 1.0;  // only the other corner is allowed
    }
    pixels[i] = occlusionAt(
        {pose.azimuth_rad + first.d_azimuth_rad, pose.elevation_rad + first.d_elevation_rad});
  }
  return pixels[1] < pixels[0] ? -1.0 : 1.0;  // the less occluded corner; a tie: +1
}

OracleAnswer OcclusionOracle::query(const SphericalPose& pose) {
  if (!environment_.hasEpisode()) throw InvalidStateError("oracle: no episode (reset first)");
  renders_ = 0;
  OracleAnswer answer;
  if (solved(occlusionAt(pose))) {
    answer.steps = 0;
    answer.target = pose;
    answer.poses_rendered = renders_;
    return answer;
  }
  if (!anchored_) {
    anchor_ = pose;
    anchored_ = true;
  }
  const SphericalCamera& camera = environment_.camera();
  // Allowed elevation offsets of the path.
  const double elevation_low = camera.lowestElevation() - pose.elevation_rad;
  const double elevation_high = camera.highestElevation() - pose.elevation_rad;
  const std::optional<Eigen::Vector2d> target_offset = nearestUnoccludedLatticeOffset(pose);
  // One step lands exactly on the circle of radius h: worth a look when the lattice's answer is
  // at most two steps.
  if (!target_offset || stepsFor(target_offset->norm(), step_rad_) <= 2) {
    if (const std::optional<Action> step = unoccludingStep(pose, elevation_low, elevation_high)) {
      answer.steps = 1;
      answer.path = {*step};
      answer.target = {pose.azimuth_rad + step->d_azimuth_rad,
                       pose.elevation_rad + step->d_elevation_rad};
      answer.poses_rendered = renders_;
      return answer;
    }
  }
  if (target_offset) {
    answer.steps = stepsFor(target_offset->norm(), step_rad_);
    if (answer.steps <= options_.max_steps) {
      const double side = answer.steps == 2
                              ? twoStepSide(pose, *target_offset, elevation_low, elevation_high)
                              : 1.0;
      answer.path =
          pathTo(*target_offset, answer.steps, step_rad_, elevation_low, elevation_high, side);
      answer.target = {pose.azimuth_rad + target_offset->x(),
                       pose.elevation_rad + target_offset->y()};
    } else {
      answer.steps = -1;
    }
  }
  answer.poses_rendered = renders_;
  return answer;
}

std::vector<std::uint8_t> OcclusionOracle::shortestFirstMoves(const SphericalPose& pose,
                                                              const OracleAnswer& answer) {
  if (answer.steps <= 0) return {};
  const SphericalCamera& camera = environment_.camera();
  const double elevation_low = camera.lowestElevation() - pose.elevation_rad;
  const double elevation_high = camera.highestElevation() - pose.elevation_rad;
  const int directions = options_.circle_directions;
  std::vector<std::uint8_t> shortest(static_cast<std::size_t>(directions), 0);
  if (answer.steps == 1) {
    // The circle query() rendered for this pose, or rendered again.
    const bool known = circle_pose_ && circle_pose_->azimuth_rad == pose.azimuth_rad &&
                       circle_pose_->elevation_rad == pose.elevation_rad;
    if (!known) unoccludingStep(pose, elevation_low, elevation_high);
    std::copy(unoccluding_.begin(), unoccluding_.end(), shortest.begin());
    return shortest;
  }
  const double reach_after = (answer.steps - 1) * step_rad_;  // from the landing pose
  const std::vector<Eigen::Vector2d> targets =
      unoccludedLatticeOffsetsWithin(pose, answer.steps * step_rad_);
  for (int k = 0; k < directions; ++k) {
    const Action step = move(2.0 * M_PI * k / directions, step_rad_);
    if (step.d_elevation_rad < elevation_low || step.d_elevation_rad > elevation_high) continue;
    const Eigen::Vector2d landing(step.d_azimuth_rad, step.d_elevation_rad);
    for (const Eigen::Vector2d& target : targets) {
      if ((target - landing).norm() <= reach_after * (1.0 + 1e-9)) {
        shortest[static_cast<std::size_t>(k)] = 1;
        break;
      }
    }
  }
  return shortest;
}

OracleAgent::OracleAgent(Environment& environment, const OracleOptions& options)
    : oracle_(environment, options) {}

void OracleAgent::reset(std::uint64_t) {
  oracle_.clear();
  plan_ = {};
  next_ = 0;
  planned_ = false;
}

Action OracleAgent::act(const RigObservation& observation) {
  if (!planned_ || next_ >= plan_.path.size()) {
    plan_ = oracle_.query(observation.pose);
    next_ = 0;
    planned_ = true;
  }
  if (next_ >= plan_.path.size()) return {1.0, 0.0};  // nothing within reach: keep circling
  return plan_.path[next_++];
}

int followOracleWithError(Environment& environment, OcclusionOracle& oracle, StepResult start,
                          double error_sd_rad, std::uint64_t seed) {
  if (!(std::isfinite(error_sd_rad) && error_sd_rad >= 0.0)) {
    throw InvalidArgumentError("the error's standard deviation must be finite and >= 0");
  }
  std::mt19937_64 random(seed);
  std::normal_distribution<double> error(0.0, 1.0);
  StepResult result = start;
  int steps = 0;
  while (!result.terminated && !result.truncated) {
    const OracleAnswer answer = oracle.query(result.info.pose);
    const double direction_rad = answer.steps > 0 ? answer.firstDirectionRad() : 0.0;
    const double move_rad = direction_rad + error_sd_rad * error(random);
    result = environment.step({std::cos(move_rad), std::sin(move_rad)});
    ++steps;
  }
  return steps;
}

AgentEntry oracleAgentEntry() {
  AgentEntry entry;
  entry.name = "oracle";
  entry.summary =
      "the fewest fixed-length steps to an unoccluded view, found by rendering other poses "
      "(reads the scene: the floor of every table, not a competitor)";
  entry.needs.simulation = true;
  entry.competes = false;
  entry.make = [](const AgentCapabilities& capabilities) {
    // Once per episode, so it can afford the finer lattice (doc/ORACLE.md): a quarter step.
    OracleOptions options;
    options.lattice_spacing_steps = 0.25;
    return std::make_unique<OracleAgent>(*capabilities.simulation, options);
  };
  return entry;
}

}  // namespace occlusion_env
