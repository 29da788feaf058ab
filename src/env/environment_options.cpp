// The environment's options, declared once (config/sim.yaml and the docs' table are checked
// against this table; the tools' flags and the simulator node's parameters come from it).
#include <cmath>

#include "occlusion_env/common/limits.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace {

using Options = EnvironmentOptions;

void addCamera(OptionTable<Options>& table) {
  table.add("width", &Options::width, OptionSpec("image width").unit("px").range(64, 1024))
      .add("height", &Options::height, OptionSpec("image height").unit("px").range(64, 1024))
      .add("field_of_view", &Options::field_of_view_rad,
           OptionSpec("horizontal field of view").unit("rad").above(0).below(M_PI))
      .add("radius", &Options::radius_m,
           OptionSpec("radius of the viewing sphere around the scene centre").unit("m").above(0))
      .add("elevation_limit", &Options::elevation_limit_rad,
           OptionSpec("elevation is clamped to +/- this").unit("rad").atLeast(0).below(M_PI / 2))
      .add("start_azimuth_range", &Options::start_azimuth_range_rad,
           OptionSpec("start azimuth ~ U(-r, r)").unit("rad").range(0, M_PI))
      .add("start_elevation", &Options::start_elevation_rad,
           OptionSpec("start elevation, within +/- elevation_limit").unit("rad"));
}

void addCameraRandomization(OptionTable<Options>& table) {
  table.add(
      "randomize_camera", [](Options& o) -> bool& { return o.camera_randomization.enabled; },
      OptionSpec("draw radius, field of view, resolution and intrinsics per scene from its "
                 "seed (the scene is scaled by drawn radius / radius)"));
  addCameraRandomizationRanges(
      table, [](Options& o) -> CameraRandomization& { return o.camera_randomization; },
      "randomize_camera: ");
}

void addObjects(OptionTable<Options>& table) {
  table
      .add(
          "catalog_source", [](Options& o) -> std::string& { return o.catalog.source; },
          OptionSpec("where objects come from")
              .choices({"embedded", "sweethome3d", "folder"})
              .flag("--source"))
      .add(
          "catalog_paths", [](Options & o) -> auto& { return o.catalog.paths; },
          OptionSpec("sweethome3d: .sh3f files or folders (empty: Debian's catalogues); "
                     "folder: exactly one root")
              .flag("--path")
              .repeatable())
      .add("lod_triangle_budget", &Options::lod_triangle_budget,
           OptionSpec("triangles per object for rendering; 0 = full meshes, else >= 12")
               .unit("triangles")
               .atLeast(0)
               .flag("--lod"))
      .add(
          "num_objects", [](Options& o) -> int& { return o.scene.num_objects; },
          OptionSpec("objects per random scene").range(1, kMaxSceneObjects).flag("--objects"))
      .add(
          "depth_spacing", [](Options& o) -> double& { return o.scene.depth_spacing_m; },
          OptionSpec("object k sits k * spacing towards +x").unit("m").atLeast(0))
      .add(
          "lateral_sigma", [](Options& o) -> double& { return o.scene.lateral_sigma_m; },
          OptionSpec("sideways offset ~ N(0, sigma), alternating sides").unit("m").atLeast(0))
      .add(
          "categories", [](Options & o) -> auto& { return o.scene.categories; },
          OptionSpec("draw only from these categories (empty: any)")
              .flag("--category")
              .repeatable())
      .add(
          "object_ids", [](Options & o) -> auto& { return o.scene.object_ids; },
          OptionSpec("use exactly these object ids, in order (overrides categories)")
              .flag("--id")
              .repeatable())
      .add("preset", &Options::preset,
           OptionSpec("scene layout (the paper's Fig. 4/5 scenes)")
               .choices({"random", "two_chairs", "two_tables"}))
      .addChoice(
          "model_split", [](const Options& o) { return toString(o.scene.model_split); },
          [](Options& o, const std::string& text) { o.scene.model_split = parseModelSplit(text); },
          OptionSpec("draw only models of this split (stable, ~80/20 per category)")
              .choices({"all", "train", "test"}))
      .add("max_scene_attempts", &Options::max_scene_attempts,
           OptionSpec("scene re-draws until the start view shows occlusion").atLeast(1));
}

void addEpisodes(OptionTable<Options>& table) {
  table
      .add("normalize_action", &Options::normalize_action,
           OptionSpec("true: each step moves exactly step_size along the action; false: the "
                      "action as given, clipped to length step_size"))
      .add("step_size", &Options::step_size_rad,
           OptionSpec("unit step").unit("rad").above(0).atMost(M_PI))
      .add("max_steps", &Options::max_steps,
           OptionSpec("steps before an episode is truncated").atLeast(1))
      .addChoice(
          "reward_normalization", [](const Options& o) { return toString(o.reward.normalization); },
          [](Options& o, const std::string& text) {
            o.reward.normalization = parseRewardNormalization(text);
          },
          OptionSpec("Z of the reward: first-frame union, first-frame occlusion, or 1")
              .choices({"union", "intersection", "none"}))
      .add(
          "success_bonus", [](Options& o) -> double& { return o.reward.success_bonus; },
          OptionSpec("reward term when the occlusion is at or below success_threshold"))
      .add(
          "step_penalty", [](Options& o) -> double& { return o.reward.step_penalty; },
          OptionSpec("reward term otherwise"))
      .add(
          "success_threshold",
          [](Options& o) -> std::int64_t& { return o.reward.success_threshold_pixels; },
          OptionSpec("occlusion at or below which the episode succeeds").unit("px").atLeast(0));
}

void addGradientAndRendering(OptionTable<Options>& table) {
  table
      .add("gradient_method", &Options::gradient_method,
           OptionSpec("the occlusion gradient's method")
               .choices({"analytic", "finite_difference"})
               .flag("--gradient"))
      .add(
          "gradient_blur_sigma", [](Options& o) -> double& { return o.gradient.blur_sigma_px; },
          OptionSpec("Gaussian smoothing of each silhouette; 0 = automatic (width * 3 / 64)")
              .unit("px")
              .range(0, 256))
      .add(
          "gradient_finite_difference_step",
          [](Options& o) -> double& { return o.gradient.finite_difference_step_rad; },
          OptionSpec("angle step of the central differences").unit("rad").above(0).atMost(0.5))
      .add(
          "gradient_zero_tolerance",
          [](Options& o) -> double& { return o.gradient.zero_gradient_tolerance; },
          OptionSpec("a gradient this short or shorter is reported as zero")
              .unit("px/rad")
              .atLeast(0))
      .add(
          "rasterizer_threads", [](Options& o) -> int& { return o.renderer.rasterizer_threads; },
          OptionSpec("llvmpipe rasteriser threads besides the calling one").range(0, 64));
}

void addWorldAndSensor(OptionTable<Options>& table) {
  table
      .add(
          "world", [](Options& o) -> std::string& { return o.world.world; },
          OptionSpec("around the targets: void (the paper's black), room (floor, walls, ceiling, "
                     "clutter, surfaces and light drawn per scene) or random (one of the two "
                     "drawn per scene)")
              .choices(worldChoices()))
      .add(
          "clutter", [](Options& o) -> int& { return o.world.clutter; },
          OptionSpec("background catalogue objects per room, outside the camera's sphere (never "
                     "counted, never in front of a target)")
              .range(0, 8))
      .add(
          "floor_clearance", [](Options& o) -> double& { return o.world.floor_clearance_m; },
          OptionSpec("room: the camera stays at least this high above the floor; lower poses are "
                     "clamped to it")
              .unit("m")
              .atLeast(0))
      .add(
          "depth_sensor", [](Options& o) -> std::string& { return o.sensor.depth_sensor; },
          OptionSpec("the camera's depth-sensor model; not ideal: colour noise, exposure, white "
                     "balance and blur too (doc/SENSORS.md); random: one drawn per scene")
              .choices(depthSensorChoices()))
      .add(
          "sensor_parameters", [](Options& o) -> std::string& { return o.sensor.parameters_file; },
          OptionSpec("YAML of the sensor models' parameters (empty: built in, = "
                     "config/sensors.yaml)"))
      .add(
          "rgb_effects", [](Options& o) -> bool& { return o.sensor.rgb_effects; },
          OptionSpec("a non-ideal sensor also degrades the colour image"));
}

OptionTable<Options> makeTable() {
  OptionTable<Options> table;
  addCamera(table);
  addCameraRandomization(table);
  addObjects(table);
  addEpisodes(table);
  addGradientAndRendering(table);
  addWorldAndSensor(table);
  return table;
}

}  // namespace

const OptionTable<EnvironmentOptions>& environmentOptionTable() {
  static const OptionTable<EnvironmentOptions> table = makeTable();
  return table;
}

}  // namespace occlusion_env
