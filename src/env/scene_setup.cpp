#include "occlusion_env/env/scene_setup.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/random.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace {

// Each draw has a stream of its own, so that turning one on changes no other draw, and none of
// them changes the scene's own stream (objects, start pose, room).
constexpr std::uint64_t kWorldStream = 0x776f726c64647277ull;
constexpr std::uint64_t kSensorStream = 0x73656e736f726472ull;
constexpr std::uint64_t kCameraStream = 0x63616d6572616472ull;

/// One of `names` (equally likely) when `value` is random, else `value`.
std::string drawChoice(const std::string& value, const std::vector<std::string>& names,
                       std::uint64_t seed) {
  if (value != kRandomChoice) return value;
  RandomSource random(seed);
  return names[random.below(names.size())];
}

/// A scaled image size, at least 16 px (CameraIntrinsics' least).
int scaledSize(int size, double scale) {
  return std::clamp(static_cast<int>(std::lround(size * scale)), 16, 4096);
}

void drawCamera(const EnvironmentOptions& options, std::uint64_t seed, SceneSetup& setup) {
  const CameraRandomization& ranges = options.camera_randomization;
  RandomSource random(seed ^ kCameraStream);
  setup.radius_m = random.uniform(ranges.radius_range_m[0], ranges.radius_range_m[1]);
  setup.field_of_view_rad =
      random.uniform(ranges.field_of_view_range_rad[0], ranges.field_of_view_range_rad[1]);
  const double resolution_scale =
      random.uniform(ranges.resolution_scale_range[0], ranges.resolution_scale_range[1]);
  setup.scene_scale = setup.radius_m / options.radius_m;
  CameraIntrinsics& k = setup.intrinsics;
  k = CameraIntrinsics::fromFieldOfView(scaledSize(options.width, resolution_scale),
                                        scaledSize(options.height, resolution_scale),
                                        setup.field_of_view_rad);
  const double focal = ranges.focal_length_jitter;
  const double centre = ranges.principal_point_jitter;
  k.fx *= 1.0 + random.uniform(-focal, focal);
  k.fy *= 1.0 + random.uniform(-focal, focal);
  k.cx += k.width * random.uniform(-centre, centre);
  k.cy += k.height * random.uniform(-centre, centre);
}

}  // namespace

nlohmann::json SceneSetup::toJson() const {
  return {{"world", world},
          {"depth_sensor", depth_sensor},
          {"camera",
           {{"radius_m", radius_m},
            {"field_of_view_rad", field_of_view_rad},
            {"scene_scale", scene_scale},
            {"width", intrinsics.width},
            {"height", intrinsics.height},
            {"fx", intrinsics.fx},
            {"fy", intrinsics.fy},
            {"cx", intrinsics.cx},
            {"cy", intrinsics.cy}}}};
}

SceneSetup SceneSetup::fromJson(const nlohmann::json& json) {
  SceneSetup setup;
  setup.world = json.at("world").get<std::string>();
  setup.depth_sensor = json.at("depth_sensor").get<std::string>();
  const nlohmann::json& camera = json.at("camera");
  setup.radius_m = camera.at("radius_m").get<double>();
  setup.field_of_view_rad = camera.at("field_of_view_rad").get<double>();
  setup.scene_scale = camera.at("scene_scale").get<double>();
  CameraIntrinsics& k = setup.intrinsics;
  k.width = camera.at("width").get<int>();
  k.height = camera.at("height").get<int>();
  k.fx = camera.at("fx").get<double>();
  k.fy = camera.at("fy").get<double>();
  k.cx = camera.at("cx").get<double>();
  k.cy = camera.at("cy").get<double>();
  return setup;
}

bool SceneSetup::operator==(const SceneSetup& other) const {
  const CameraIntrinsics& a = intrinsics;
  const CameraIntrinsics& b = other.intrinsics;
  return world == other.world && depth_sensor == other.depth_sensor && radius_m == other.radius_m &&
         field_of_view_rad == other.field_of_view_rad && scene_scale == other.scene_scale &&
         a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy &&
         a.cx == b.cx && a.cy == b.cy;
}

SceneSetup drawSceneSetup(const EnvironmentOptions& options, std::uint64_t seed) {
  SceneSetup setup;
  setup.world = drawChoice(options.world.world, {"void", "room"}, seed ^ kWorldStream);
  setup.depth_sensor =
      drawChoice(options.sensor.depth_sensor, depthSensorNames(), seed ^ kSensorStream);
  if (options.camera_randomization.enabled) {
    drawCamera(options, seed, setup);
  } else {
    setup.radius_m = options.radius_m;
    setup.field_of_view_rad = options.field_of_view_rad;
    setup.intrinsics =
        CameraIntrinsics::fromFieldOfView(options.width, options.height, options.field_of_view_rad);
  }
  return setup;
}

const std::vector<std::string>& worldChoices() {
  static const std::vector<std::string> choices = {"void", "room", kRandomChoice};
  return choices;
}

const std::vector<std::string>& depthSensorChoices() {
  static const std::vector<std::string> choices = {"ideal", "kinect_v1", "realsense_d435",
                                                   "azure_kinect", kRandomChoice};
  return choices;
}

const OptionTable<CameraRandomization>& cameraRangeTable() {
  static const auto table = [] {
    OptionTable<CameraRandomization> ranges;
    addCameraRandomizationRanges(
        ranges, [](CameraRandomization& r) -> CameraRandomization& { return r; }, "");
    return ranges;
  }();
  return table;
}

void requireCameraRangesDrawn(const CameraRandomization& ranges, bool randomize) {
  if (!randomize) {
    const nlohmann::json given = cameraRangeTable().toJson(ranges);
    const nlohmann::json defaults = cameraRangeTable().toJson(CameraRandomization{});
    for (const std::string& key : cameraRangeTable().keys()) {
      if (given.at(key) != defaults.at(key)) {
        throw InvalidArgumentError(key +
                                   " is a range the camera is drawn from: it needs randomize");
      }
    }
  }
  EnvironmentOptions drawn;  // min <= max, checked where the environment checks them
  drawn.camera_randomization = ranges;
  drawn.camera_randomization.enabled = randomize;
  drawn.validate();
}

void applySceneRandomization(EnvironmentOptions& options, const std::optional<std::string>& world,
                             const std::optional<std::string>& depth_sensor, bool randomize) {
  options.camera_randomization.enabled = randomize;
  if (world || randomize) options.world.world = world.value_or(kRandomChoice);
  if (depth_sensor || randomize) options.sensor.depth_sensor = depth_sensor.value_or(kRandomChoice);
}

}  // namespace occlusion_env
