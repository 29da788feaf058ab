// The occlusion landscape: the grid's poses, L at the start view equal to the episode's own, the
// episode left as it was, and the grid around the agents' paths.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "occlusion_env/agents/agent.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/eval/landscape.hpp"

namespace occlusion_env {
namespace eval {
namespace {

TEST(Landscape, SamplesTheGridAndLeavesTheEpisodeAlone) {
  EnvironmentOptions options;
  options.width = options.height = 64;
  Environment env(options);
  const std::string path = ::testing::TempDir() + "/landscape.csv";
  EXPECT_THROW(writeOcclusionLandscapeCsv(env, {}, path), InvalidArgumentError);  // no episode

  ResetOptions reset;
  reset.start_azimuth_rad = 0.0;
  env.reset(3, reset);
  const std::int64_t start_occlusion = env.info().occlusion.total_pixels;
  ASSERT_GT(start_occlusion, 0);
  LandscapeGrid grid;
  grid.azimuth_min_rad = -0.1;
  grid.azimuth_max_rad = 0.1;
  grid.elevation_min_rad = 0.0;
  grid.elevation_max_rad = 0.05;
  grid.spacing_rad = 0.05;
  EXPECT_EQ(writeOcclusionLandscapeCsv(env, grid, path), 5 * 2);

  std::ifstream in(path);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "azimuth_rad,elevation_rad,occlusion_px");
  int rows = 0;
  bool saw_start = false;
  while (std::getline(in, line)) {
    ++rows;
    double azimuth = 0.0, elevation = 0.0;
    long long occlusion = -1;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lld", &azimuth, &elevation, &occlusion), 3);
    EXPECT_GE(occlusion, 0);
    if (std::abs(azimuth) < 1e-12 && std::abs(elevation) < 1e-12) {
      saw_start = true;
      EXPECT_EQ(occlusion, start_occlusion);  // the same view, the same L
    }
  }
  EXPECT_EQ(rows, 10);
  EXPECT_TRUE(saw_start);
  EXPECT_EQ(env.info().occlusion.total_pixels, start_occlusion);
  EXPECT_EQ(env.info().step_index, 0);

  grid.spacing_rad = 0.0;
  EXPECT_THROW(writeOcclusionLandscapeCsv(env, grid, path), InvalidArgumentError);
  grid.spacing_rad = 1e-5;  // far more than 100,000 poses
  EXPECT_THROW(writeOcclusionLandscapeCsv(env, grid, path), InvalidArgumentError);
  std::remove(path.c_str());
}

TEST(Landscape, GridHoldsEveryPathPoseWithinTheCamerasElevations) {
  EpisodeRecord first;
  first.agent = "gradient";
  first.path = {{0.2, 0.0}, {-0.9, 0.1}};
  EpisodeRecord second;
  second.agent = "random";
  second.path = {{0.2, 0.0}, {0.5, -1.3}};
  const LandscapeGrid grid = gridAround({first, second}, 0.1, 0.3, 0.025, -1.2, 0.25);
  EXPECT_DOUBLE_EQ(grid.azimuth_min_rad, -1.0);
  EXPECT_DOUBLE_EQ(grid.azimuth_max_rad, 0.6);
  EXPECT_DOUBLE_EQ(grid.elevation_min_rad, -1.2);  // -1.4 clamped to the lowest
  EXPECT_DOUBLE_EQ(grid.elevation_max_rad, 0.25);  // the start's + 0.3 clamped to the highest
  EXPECT_DOUBLE_EQ(grid.spacing_rad, 0.025);
}

}  // namespace
}  // namespace eval
}  // namespace occlusion_env
