// The shipped configuration must state the core's defaults: config/sim.yaml is what users read
// to learn them, so a default changed in one place and not the other fails here.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>

#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/occlusion/occlusion_gradient.hpp"

namespace occlusion_env {
namespace {

TEST(ShippedConfigTest, SimYamlStatesTheEnvironmentDefaults) {
  const YAML::Node yaml =
      YAML::LoadFile(std::string(OCCLUSION_ENV_SOURCE_DIR) + "/config/sim.yaml");
  const EnvironmentOptions defaults;
  EXPECT_EQ(yaml["width"].as<int>(), defaults.width);
  EXPECT_EQ(yaml["height"].as<int>(), defaults.height);
  EXPECT_NEAR(yaml["field_of_view"].as<double>(), defaults.field_of_view_rad, 1e-9);
  EXPECT_DOUBLE_EQ(yaml["radius"].as<double>(), defaults.radius_m);
  EXPECT_NEAR(yaml["elevation_limit"].as<double>(), defaults.elevation_limit_rad, 1e-9);
  EXPECT_NEAR(yaml["start_azimuth_range"].as<double>(), defaults.start_azimuth_range_rad, 1e-9);
  EXPECT_DOUBLE_EQ(yaml["start_elevation"].as<double>(), defaults.start_elevation_rad);
  EXPECT_EQ(yaml["catalog_source"].as<std::string>(), defaults.catalog.source);
  EXPECT_EQ(yaml["catalog_paths"].size(), defaults.catalog.paths.size());
  EXPECT_EQ(yaml["lod_triangle_budget"].as<std::size_t>(), defaults.lod_triangle_budget);
  EXPECT_EQ(yaml["num_objects"].as<int>(), defaults.scene.num_objects);
  EXPECT_DOUBLE_EQ(yaml["depth_spacing"].as<double>(), defaults.scene.depth_spacing_m);
  EXPECT_DOUBLE_EQ(yaml["lateral_sigma"].as<double>(), defaults.scene.lateral_sigma_m);
  EXPECT_EQ(yaml["categories"].size(), defaults.scene.categories.size());
  EXPECT_EQ(yaml["object_ids"].size(), defaults.scene.object_ids.size());
  EXPECT_EQ(yaml["preset"].as<std::string>(), defaults.preset);
  EXPECT_EQ(yaml["max_scene_attempts"].as<int>(), defaults.max_scene_attempts);
  EXPECT_EQ(yaml["normalize_action"].as<bool>(), defaults.normalize_action);
  EXPECT_DOUBLE_EQ(yaml["step_size"].as<double>(), defaults.step_size_rad);
  EXPECT_EQ(yaml["max_steps"].as<int>(), defaults.max_steps);
  EXPECT_EQ(yaml["reward_normalization"].as<std::string>(),
            toString(defaults.reward.normalization));
  EXPECT_DOUBLE_EQ(yaml["success_bonus"].as<double>(), defaults.reward.success_bonus);
  EXPECT_DOUBLE_EQ(yaml["step_penalty"].as<double>(), defaults.reward.step_penalty);
  EXPECT_EQ(yaml["success_threshold"].as<std::int64_t>(), defaults.reward.success_threshold_pixels);

  const OcclusionGradientOptions gradient;
  EXPECT_EQ(yaml["gradient_method"].as<std::string>(), "analytic");
  EXPECT_DOUBLE_EQ(yaml["gradient_blur_sigma"].as<double>(), gradient.blur_sigma_px);
  EXPECT_DOUBLE_EQ(yaml["gradient_finite_difference_step"].as<double>(),
                   gradient.finite_difference_step_rad);
  EXPECT_DOUBLE_EQ(yaml["gradient_zero_tolerance"].as<double>(), gradient.zero_gradient_tolerance);
  EXPECT_EQ(yaml["gradient_method"].as<std::string>(), defaults.gradient_method);
  EXPECT_EQ(yaml["rasterizer_threads"].as<int>(), defaults.renderer.rasterizer_threads);
  EXPECT_EQ(yaml["model_split"].as<std::string>(), toString(defaults.scene.model_split));
}

}  // namespace
}  // namespace occlusion_env
