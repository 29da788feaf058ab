// The occlusion L over a grid of camera angles around a scene's start view, with the paths the
// agents take on it: a picture of the search space the agents move through.
#pragma once

#include <string>
#include <vector>

#include "occlusion_env/agents/episode.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace eval {

/// Camera angles [rad] at which L is sampled: a regular grid, both ends included.
struct LandscapeGrid {
  double azimuth_min_rad = -1.0;
  double azimuth_max_rad = 1.0;
  double elevation_min_rad = -0.5;
  double elevation_max_rad = 0.5;
  double spacing_rad = 0.025;
};

/// Writes `azimuth_rad,elevation_rad,occlusion_px` for every grid pose of `env`'s current scene
/// (Environment::renderAt: the episode is not changed). Returns the number of poses. Throws
/// InvalidArgumentError for an empty or too fine grid (more than 100,000 poses) or no episode.
int writeOcclusionLandscapeCsv(Environment& env, const LandscapeGrid& grid,
                               const std::string& path);

/// Writes `agent,success,steps,t,azimuth_rad,elevation_rad`, one row per pose of each episode's
/// path.
void writeEpisodePathsCsv(const std::vector<EpisodeRecord>& episodes, const std::string& path);

/// The grid around `paths` (all poses inside, with `margin_rad` to spare on each side, at least
/// +/- `min_half_width_rad` around the first path's start) at `spacing_rad`, elevations within
/// [lowest_elevation_rad, highest_elevation_rad] (the camera's: SphericalCamera).
LandscapeGrid gridAround(const std::vector<EpisodeRecord>& paths, double margin_rad,
                         double min_half_width_rad, double spacing_rad, double lowest_elevation_rad,
                         double highest_elevation_rad);

}  // namespace eval
}  // namespace occlusion_env
