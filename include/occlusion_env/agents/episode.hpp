// One episode of an agent: the record every runner, tool and node produces, its CSV form (one
// schema, with a version column) and the statistics over many episodes. The ROS message
// occlusion_env/EpisodeReport converts to and from it (ros/msg_conversion.hpp).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "occlusion_env/geometry/camera.hpp"
#include "occlusion_env/occlusion/occlusion.hpp"

namespace occlusion_env {

/// How an episode ended. The first three and kUnusableView are outcomes (the statistics count the
/// failures at the step limit); the others cut it short.
enum class EpisodeEnd {
  kSuccess,           // the view became unoccluded (the environment terminated the episode)
  kTruncated,         // the environment's own step limit
  kStepLimit,         // the runner's step limit
  kEnvironmentError,  // the environment refused or failed a reset or step (the message says why)
  kEnvironmentLost,   // the environment could not be reached (a remote simulator went away)
  kAgentFailed,       // the agent could not act on an observation (the message says why)
  kStopped,           // the runner was asked to stop (e.g. the node shuts down)
  kUnusableView,      // a camera's view could not be used (UnusableViewError): a failure
};

/// "success", "truncated", "step_limit", "environment_error", "environment_lost", "agent_failed",
/// "stopped", "unusable_view".
const char* toString(EpisodeEnd end);
/// The inverse of toString(); throws InvalidArgumentError for any other text.
EpisodeEnd parseEpisodeEnd(const std::string& text);

struct EpisodeRecord {
  std::string agent;
  std::string scene_set;  // a scene set's name, "sweep_<preset>", or what a node was given
  std::uint64_t scene_seed = 0;
  double start_azimuth_rad = 0.0;  // the requested start azimuth, else the start pose's
  int max_steps = 0;               // the runner's step limit
  int steps = 0;                   // steps taken
  EpisodeEnd end = EpisodeEnd::kStepLimit;
  std::int64_t final_occlusion_px = -1;  // L (Eq. 9) of the last view [px]; -1: never observed
  // Of `end` and final_occlusion_px: an estimate behind a real camera (not in the CSV).
  OcclusionSource occlusion_source = OcclusionSource::kGroundTruth;
  double wall_time_s = 0.0;         // reset, steps and the agent's own work
  std::string message;              // why it was cut short; empty otherwise
  std::vector<SphericalPose> path;  // the start pose, then one per step

  bool success() const { return end == EpisodeEnd::kSuccess; }
  /// Ran to an outcome (success, a step limit, or a camera view that could not be used), not cut
  /// short.
  bool completed() const {
    return end == EpisodeEnd::kSuccess || end == EpisodeEnd::kTruncated ||
           end == EpisodeEnd::kStepLimit || end == EpisodeEnd::kUnusableView;
  }
  /// Steps for the statistics: a failed episode counts as the step limit.
  int countedSteps() const { return success() ? steps : max_steps; }
};

/// The CSV schema. Version 2 columns: version, agent, scene_set, scene_seed, start_azimuth_rad,
/// max_steps, steps, success, final_occlusion_px, wall_time_s, end, message, azimuths_rad,
/// elevations_rad (the path, `;`-separated). Version 1 (the first nine columns of version 2
/// without `version`) is still read.
constexpr int kEpisodeCsvVersion = 2;
std::string episodeCsvHeader();  // no newline
/// One row (with newline). Agent and scene-set names must be non-empty without commas, quotes or
/// line breaks (InvalidArgumentError); such characters in the message become spaces.
void writeEpisodeCsvRow(std::ostream& out, const EpisodeRecord& record);
/// Reads a file written with the functions above. Throws InvalidArgumentError naming the line.
std::vector<EpisodeRecord> readEpisodeCsv(const std::string& path);

/// Statistics of a group of episodes (one agent's, usually). Steps count failures as the limit.
struct EpisodeStatistics {
  int episodes = 0;   // all records given
  int completed = 0;  // of them, not cut short: the ones the figures below are over
  int successes = 0;
  int max_steps = 0;        // the largest step limit among the completed episodes
  double mean_steps = 0.0;  // counted steps; NaN when none completed
  double sd_steps = 0.0;    // sample standard deviation (n - 1); NaN for fewer than two
  double mean_wall_time_s = 0.0;
  double successRate() const { return completed > 0 ? double(successes) / completed : 0.0; }
};
EpisodeStatistics summarizeEpisodes(const std::vector<EpisodeRecord>& records);

}  // namespace occlusion_env
