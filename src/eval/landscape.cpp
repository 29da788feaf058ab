#include "occlusion_env/eval/landscape.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/occlusion/occlusion.hpp"

namespace occlusion_env {
namespace eval {
namespace {

constexpr int kMaxPoses = 100'000;

int samples(double min, double max, double spacing) {
  return static_cast<int>(std::floor((max - min) / spacing + 1e-9)) + 1;
}

}  // namespace

int writeOcclusionLandscapeCsv(Environment& env, const LandscapeGrid& grid,
                               const std::string& path) {
  if (!env.hasEpisode())
    throw InvalidArgumentError("occlusion landscape: no episode (reset first)");
  if (!(grid.spacing_rad > 0.0) || !(grid.azimuth_max_rad >= grid.azimuth_min_rad) ||
      !(grid.elevation_max_rad >= grid.elevation_min_rad)) {
    throw InvalidArgumentError("occlusion landscape: empty grid or spacing <= 0");
  }
  const int azimuths = samples(grid.azimuth_min_rad, grid.azimuth_max_rad, grid.spacing_rad);
  const int elevations = samples(grid.elevation_min_rad, grid.elevation_max_rad, grid.spacing_rad);
  if (static_cast<double>(azimuths) * elevations > kMaxPoses) {
    throw InvalidArgumentError("occlusion landscape: more than 100,000 poses; use a coarser grid");
  }
  std::ofstream out(path);
  if (!out) throw InvalidArgumentError("cannot write " + path);
  out << "azimuth_rad,elevation_rad,occlusion_px\n" << std::setprecision(9);
  const int num_objects = static_cast<int>(env.scene().objects.size());
  for (int e = 0; e < elevations; ++e) {
    for (int a = 0; a < azimuths; ++a) {
      const SphericalPose pose{grid.azimuth_min_rad + a * grid.spacing_rad,
                               grid.elevation_min_rad + e * grid.spacing_rad};
      const RenderBuffers& buffers = env.renderAt(pose);
      const OcclusionStats stats = computeOcclusion(buffers.amodal_bits, num_objects, nullptr);
      out << pose.azimuth_rad << ',' << pose.elevation_rad << ',' << stats.total_pixels << '\n';
    }
  }
  return azimuths * elevations;
}

void writeEpisodePathsCsv(const std::vector<EpisodeRecord>& episodes, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw InvalidArgumentError("cannot write " + path);
  out << "agent,success,steps,t,azimuth_rad,elevation_rad\n" << std::setprecision(9);
  for (const EpisodeRecord& episode : episodes) {
    for (std::size_t t = 0; t < episode.path.size(); ++t) {
      out << episode.agent << ',' << (episode.success() ? 1 : 0) << ',' << episode.steps << ',' << t
          << ',' << episode.path[t].azimuth_rad << ',' << episode.path[t].elevation_rad << '\n';
    }
  }
}

LandscapeGrid gridAround(const std::vector<EpisodeRecord>& paths, double margin_rad,
                         double min_half_width_rad, double spacing_rad, double lowest_elevation_rad,
                         double highest_elevation_rad) {
  LandscapeGrid grid;
  grid.spacing_rad = spacing_rad;
  double start_azimuth = 0.0, start_elevation = 0.0;
  if (!paths.empty() && !paths.front().path.empty()) {
    start_azimuth = paths.front().path.front().azimuth_rad;
    start_elevation = paths.front().path.front().elevation_rad;
  }
  grid.azimuth_min_rad = start_azimuth - min_half_width_rad;
  grid.azimuth_max_rad = start_azimuth + min_half_width_rad;
  grid.elevation_min_rad = start_elevation - min_half_width_rad;
  grid.elevation_max_rad = start_elevation + min_half_width_rad;
  for (const EpisodeRecord& episode : paths) {
    for (const SphericalPose& pose : episode.path) {
      grid.azimuth_min_rad = std::min(grid.azimuth_min_rad, pose.azimuth_rad - margin_rad);
      grid.azimuth_max_rad = std::max(grid.azimuth_max_rad, pose.azimuth_rad + margin_rad);
      grid.elevation_min_rad = std::min(grid.elevation_min_rad, pose.elevation_rad - margin_rad);
      grid.elevation_max_rad = std::max(grid.elevation_max_rad, pose.elevation_rad + margin_rad);
    }
  }
  grid.elevation_min_rad = std::max(grid.elevation_min_rad, lowest_elevation_rad);
  grid.elevation_max_rad = std::min(grid.elevation_max_rad, highest_elevation_rad);
  return grid;
}

}  // namespace eval
}  // namespace occlusion_env
