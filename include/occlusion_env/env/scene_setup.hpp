// What surrounds and sees one scene: its world, depth sensor and camera, fixed by the options or
// drawn per scene from the scene's seed (domain randomisation, doc/SENSORS.md). Off by default:
// the paper's fixed camera in the void through an ideal sensor.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/geometry/camera.hpp"

namespace occlusion_env {

struct EnvironmentOptions;

/// The `world` and `depth_sensor` value that draws one per scene.
constexpr const char* kRandomChoice = "random";

/// The values `world` and `depth_sensor` take (kRandomChoice included), for every option table.
const std::vector<std::string>& worldChoices();
const std::vector<std::string>& depthSensorChoices();

/// Per-scene draws of the camera (environment options `randomize_camera`, ...). The scene keeps
/// the options' geometry (camera at `radius` in the scene's own units) and is scaled by
/// drawn radius / radius, so the camera stands radius_range metres from a scene of that size.
struct CameraRandomization {
  bool enabled = false;
  std::vector<double> radius_range_m{0.5, 1.5};                         // [m], min, max
  std::vector<double> field_of_view_range_rad{M_PI / 3.0, M_PI / 2.0};  // horizontal [rad]
  std::vector<double> resolution_scale_range{0.5, 1.0};                 // times width and height
  double focal_length_jitter = 0.03;     // fx and fy each times 1 + U(-j, j)
  double principal_point_jitter = 0.02;  // cx, cy each + U(-j, j) times width, height [px]
};

/// One scene's world, sensor and camera.
struct SceneSetup {
  std::string world = "void";          // void | room
  std::string depth_sensor = "ideal";  // ideal | kinect_v1 | realsense_d435 | azure_kinect
  double radius_m = 4.0;               // of the camera's sphere in the (scaled) world [m]
  double field_of_view_rad = 0.0;      // horizontal, before the focal-length jitter [rad]
  double scene_scale = 1.0;            // world metres per metre of the scene's models
  CameraIntrinsics intrinsics;         // what the renderer and camera_info use

  /// {world, depth_sensor, camera: {radius_m, field_of_view_rad, scene_scale, width, height, fx,
  /// fy, cx, cy}}: what a frame's labels record.
  nlohmann::json toJson() const;
  /// The inverse of toJson(); throws nlohmann::json::exception on a missing member.
  static SceneSetup fromJson(const nlohmann::json& json);
  bool operator==(const SceneSetup& other) const;
};

/// The setup of the scene drawn from `seed`: the options' world, sensor and camera, with each
/// `random` choice and, with camera randomisation, the camera drawn from streams of their own
/// (the scene's objects and start pose draw exactly as without).
SceneSetup drawSceneSetup(const EnvironmentOptions& options, std::uint64_t seed);

/// For a tool's options: throws InvalidArgumentError when `ranges` differ from the defaults and
/// the camera is not drawn (`randomize` false), and when a range's min exceeds its max.
void requireCameraRangesDrawn(const CameraRandomization& ranges, bool randomize);

/// What the tools' --world, --depth-sensor and --randomize ask for: `randomize` draws the camera
/// per scene and, where `world` / `depth_sensor` are not given, the world and the sensor too.
void applySceneRandomization(EnvironmentOptions& options, const std::optional<std::string>& world,
                             const std::optional<std::string>& depth_sensor, bool randomize);

/// Adds those three options (world, depth_sensor, randomize: --world, --depth-sensor,
/// --randomize) to a tool's table; `scope` begins each help text (e.g. "with --scenes: ").
template <class O>
OptionTable<O>& addSceneRandomizationOptions(OptionTable<O>& table,
                                             std::optional<std::string> O::*world,
                                             std::optional<std::string> O::*depth_sensor,
                                             bool O::*randomize, const std::string& scope = "") {
  return table
      .add("world", world,
           OptionSpec(scope + "around the targets (unset: void, or random with --randomize), " +
                      "drawn from each scene's seed")
               .choices(worldChoices()))
      .add("depth_sensor", depth_sensor,
           OptionSpec(scope + "the camera's depth sensor; the images are what it gives (unset: " +
                      "ideal, or random with --randomize)")
               .choices(depthSensorChoices()))
      .add("randomize", randomize,
           OptionSpec(scope + "draw per scene the camera (radius, field of view, resolution, " +
                      "intrinsics) and, unless given, world and depth sensor (doc/SENSORS.md)"));
}

/// Adds the ranges of the camera draws (radius_range, field_of_view_range,
/// resolution_scale_range, focal_length_jitter, principal_point_jitter) of the
/// CameraRandomization that `ranges(options)` returns to a table: the environment's, and the
/// tools' that make randomised scenes. `scope` begins each help text.
template <class O, class Ranges>
OptionTable<O>& addCameraRandomizationRanges(OptionTable<O>& table, Ranges ranges,
                                             const std::string& scope) {
  const auto field = [ranges](auto CameraRandomization::*member) {
    return [ ranges, member ](O & options) -> auto& {
      return ranges(options).*member;
    };
  };
  return table
      .add("radius_range", field(&CameraRandomization::radius_range_m),
           OptionSpec(scope + "the camera's distance from the scene centre, min,max")
               .unit("m")
               .above(0))
      .add("field_of_view_range", field(&CameraRandomization::field_of_view_range_rad),
           OptionSpec(scope + "horizontal field of view, min,max").unit("rad").above(0).below(M_PI))
      .add("resolution_scale_range", field(&CameraRandomization::resolution_scale_range),
           OptionSpec(scope + "image size = width, height times this, min,max").range(0.0625, 4))
      .add("focal_length_jitter", field(&CameraRandomization::focal_length_jitter),
           OptionSpec(scope + "fx and fy each times 1 + U(-j, j)").range(0, 0.5))
      .add("principal_point_jitter", field(&CameraRandomization::principal_point_jitter),
           OptionSpec(scope + "cx and cy each moved by U(-j, j) times width, height")
               .range(0, 0.25));
}

/// The camera's ranges alone, by the names of every table that has them (their keys() and toJson
/// compare and record them).
const OptionTable<CameraRandomization>& cameraRangeTable();

}  // namespace occlusion_env
