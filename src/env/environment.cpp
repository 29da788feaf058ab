#include "occlusion_env/env/environment.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/render/osmesa_renderer.hpp"

namespace occlusion_env {
namespace {

void require(bool condition, const std::string& option, const std::string& expectation,
             double value) {
  if (condition) return;
  std::ostringstream message;
  message << "option '" << option << "' must be " << expectation << ", got " << value;
  throw InvalidArgumentError(message.str());
}

std::unique_ptr<Renderer> rendererFor(const EnvironmentOptions& options,
                                      const CameraIntrinsics& intrinsics) {
  std::unique_ptr<Renderer> renderer = options.renderer_factory
                                           ? options.renderer_factory(intrinsics, options.renderer)
                                           : makeOsMesaRenderer(intrinsics, options.renderer);
  if (!renderer) throw InvalidArgumentError("the renderer factory made no renderer");
  return renderer;
}

bool sameIntrinsics(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy &&
         a.cx == b.cx && a.cy == b.cy;
}

/// The setup before the first reset: the options' camera, world and sensor (void and ideal where
/// they are drawn per scene).
SceneSetup initialSetup(const EnvironmentOptions& options) {
  EnvironmentOptions fixed = options;
  fixed.camera_randomization.enabled = false;
  if (fixed.world.world == kRandomChoice) fixed.world.world = "void";
  if (fixed.sensor.depth_sensor == kRandomChoice) fixed.sensor.depth_sensor = "ideal";
  return drawSceneSetup(fixed, 0);
}

/// The simulator's episode rule: the true occlusion ends an episode on its first clear view.
EpisodeRuleOptions simulatorEpisodeRule(const EnvironmentOptions& options) {
  EpisodeRuleOptions rule;
  rule.reward = options.reward;
  rule.max_steps = options.max_steps;
  rule.confirm_views = 1;
  return rule;
}

std::shared_ptr<ObjectLibrary> libraryFor(const EnvironmentOptions& options) {
  std::shared_ptr<const ObjectCatalog> catalog = makeCatalog(options.catalog);
  return std::make_shared<ObjectLibrary>(std::move(catalog), options.lod_triangle_budget);
}

void requireRange(const std::vector<double>& range, const std::string& option) {
  if (range.size() != 2 || !(range[0] <= range[1])) {
    throw InvalidArgumentError("option '" + option +
                               "' must be two numbers, min,max with min <= max");
  }
}

/// The scene options of a reset: the environment's with the overrides' objects. Throws
/// InvalidArgumentError for bad overrides.
SceneOptions sceneOptionsFor(const EnvironmentOptions& options, const ResetOptions& overrides) {
  SceneOptions scene_options = options.scene;
  if (!overrides.object_ids.empty()) scene_options.object_ids = overrides.object_ids;
  if (!overrides.categories.empty()) scene_options.categories = overrides.categories;
  if (scene_options.object_ids.size() > static_cast<std::size_t>(kMaxSceneObjects)) {
    throw InvalidArgumentError("a scene holds at most " + std::to_string(kMaxSceneObjects) +
                               " objects");
  }
  if (overrides.start_azimuth_rad && !std::isfinite(*overrides.start_azimuth_rad)) {
    throw InvalidArgumentError("start azimuth must be finite");
  }
  if (overrides.start_elevation_rad && !std::isfinite(*overrides.start_elevation_rad)) {
    throw InvalidArgumentError("start elevation must be finite");
  }
  if (overrides.start_elevation_rad &&
      !(std::abs(*overrides.start_elevation_rad) <= options.elevation_limit_rad)) {
    throw InvalidArgumentError("start elevation must lie within +/- the elevation limit");
  }
  return scene_options;
}

}  // namespace

void EnvironmentOptions::validate() const {
  environmentOptionTable().check(*this);
  requireRange(camera_randomization.radius_range_m, "radius_range");
  requireRange(camera_randomization.field_of_view_range_rad, "field_of_view_range");
  requireRange(camera_randomization.resolution_scale_range, "resolution_scale_range");
  require(std::abs(start_elevation_rad) <= elevation_limit_rad, "start_elevation",
          "within +/- elevation_limit", start_elevation_rad);
  require(lod_triangle_budget == 0 || lod_triangle_budget >= 12, "lod_triangle_budget",
          "0 (off) or at least 12 triangles", static_cast<double>(lod_triangle_budget));
  require(scene.object_ids.size() <= static_cast<std::size_t>(kMaxSceneObjects), "object_ids",
          "at most " + std::to_string(kMaxSceneObjects) + " ids long",
          static_cast<double>(scene.object_ids.size()));
  if (catalog.source == "folder" && catalog.paths.size() != 1) {
    throw InvalidArgumentError(
        "catalog_paths must hold exactly one root folder when catalog_source is folder");
  }
  // `random` draws one of the concrete choices, each valid with the other options.
  SensorOptions concrete_sensor = sensor;
  if (concrete_sensor.depth_sensor == kRandomChoice) concrete_sensor.depth_sensor = "ideal";
  concrete_sensor.validate();
  WorldOptions concrete_world = world;
  if (concrete_world.world == kRandomChoice) concrete_world.world = "void";
  concrete_world.validate();
}

Environment::Environment(const EnvironmentOptions& options, std::shared_ptr<ObjectLibrary> library)
    : options_((options.validate(), options)),
      camera_(options.radius_m, options.elevation_limit_rad),
      library_(library ? std::move(library) : libraryFor(options)),
      setup_(initialSetup(options)),
      rule_(simulatorEpisodeRule(options)) {
  renderer_ = rendererFor(options, setup_.intrinsics);
  sensors_.resize(depthSensorNames().size());
  sensor_ = &sensorFor(setup_.depth_sensor);
}

CameraSensor& Environment::sensorFor(const std::string& depth_sensor) {
  const std::vector<std::string>& names = depthSensorNames();
  const auto index =
      static_cast<std::size_t>(std::find(names.begin(), names.end(), depth_sensor) - names.begin());
  if (index >= names.size()) throw InvalidArgumentError("unknown depth sensor " + depth_sensor);
  if (!sensors_[index]) {
    SensorOptions sensor_options = options_.sensor;
    sensor_options.depth_sensor = depth_sensor;
    sensors_[index] = std::make_unique<CameraSensor>(sensor_options);
  }
  return *sensors_[index];
}

Environment::~Environment() = default;

GradientResult Environment::occlusionGradient() {
  if (!gradient_) gradient_ = makeOcclusionGradient(options_.gradient_method, options_.gradient);
  return gradient_->compute(*this);
}

PrivilegedObservation Environment::privilegedObservation() {
  if (!has_episode_) throw InvalidStateError("privilegedObservation() before any reset()");
  return {observation_.instance, observation_.amodal_bits, observation_.occlusion_mask,
          info_.occlusion};
}

const CameraIntrinsics& Environment::intrinsics() const {
  return renderer_->intrinsics();
}

void Environment::placeScene(const Scene& scene, const Room* room) {
  std::vector<PlacedMesh> placed;
  placed.reserve(scene.objects.size());
  for (const SceneObject& object : scene.objects) {
    PlacedMesh mesh;
    mesh.mesh = &object.model->render;
    mesh.world_from_object = Eigen::Translation3d(object.position_m);
    if (scene.scale != 1.0) mesh.world_from_object.prescale(scene.scale);
    placed.push_back(mesh);
  }
  renderer_->setScene(placed);
  // The void: nothing around the objects and the default light, also after a room on this
  // renderer (a reset keeps the renderer while the camera's intrinsics stay the same).
  if (!room) {
    renderer_->setBackground(SceneBackground{});
    return;
  }
  // The room scales with the scene (its floor, walls and ceiling too), so that a camera drawn
  // nearer sees the same picture at another scale.
  SceneBackground background = room->background();
  if (scene.scale != 1.0) {
    for (auto* meshes : {&background.one_sided, &background.two_sided}) {
      for (PlacedMesh& mesh : *meshes) mesh.world_from_object.prescale(scene.scale);
    }
    const auto scale = static_cast<float>(scene.scale);
    for (TiledSurface& surface : background.tiled) {
      surface.origin *= scale;
      surface.step_u *= scale;
      surface.step_v *= scale;
    }
  }
  renderer_->setBackground(background);
}

StepResult Environment::reset(std::uint64_t seed, const ResetOptions& overrides) {
  const ScenePreset preset = parseScenePreset(overrides.preset.value_or(options_.preset));
  const SceneOptions scene_options = sceneOptionsFor(options_, overrides);

  const SceneSetup setup = drawSceneSetup(options_, seed);
  RandomSource random(seed);
  const double azimuth_range = options_.start_azimuth_range_rad;
  const double drawn_azimuth = random.uniform(-azimuth_range, azimuth_range);
  const SphericalPose requested_start{
      overrides.start_azimuth_rad.value_or(drawn_azimuth),
      overrides.start_elevation_rad.value_or(options_.start_elevation_rad)};
  CameraSensor& sensor = sensorFor(setup.depth_sensor);
  // Another camera needs another renderer; the current one is kept until a scene is accepted.
  std::unique_ptr<Renderer> previous_renderer;
  if (!sameIntrinsics(setup.intrinsics, renderer_->intrinsics())) {
    std::unique_ptr<Renderer> renderer = rendererFor(options_, setup.intrinsics);
    previous_renderer = std::exchange(renderer_, std::move(renderer));
  }
  const auto restore = [this, &previous_renderer] {
    if (previous_renderer) {
      renderer_ = std::move(previous_renderer);  // its scene was never changed
    } else if (has_episode_) {
      placeScene(scene_, room_.get());  // the renderer draws the current episode again
    }
  };

  // Draw scenes until the start view shows occlusion. Candidates render into the probe buffers,
  // so the current episode stays intact until one is accepted.
  const int num_attempts = options_.max_scene_attempts;
  try {
    for (int attempt = 0; attempt < num_attempts; ++attempt) {
      Scene candidate = generateScene(*library_, scene_options, preset, random);
      candidate.scale = setup.scene_scale;
      std::unique_ptr<Room> candidate_room = roomFor(candidate, setup, random);
      const SphericalCamera camera = cameraFor(setup, candidate_room.get());
      const SphericalPose start_pose = camera.normalized(requested_start);
      const Eigen::Isometry3d world_from_optical = camera.worldFromOptical(start_pose);
      placeScene(candidate, candidate_room.get());
      renderer_->render(world_from_optical, probe_buffers_);
      const int num_objects = static_cast<int>(candidate.objects.size());
      OcclusionStats occlusion = computeOcclusion(probe_buffers_.amodal_bits, num_objects,
                                                  probe_buffers_.target_footprint);
      if (rule_.reward().solved(occlusion.total_pixels)) continue;  // the threshold only, not Z

      scene_ = std::move(candidate);
      room_ = std::move(candidate_room);
      setup_ = setup;
      camera_ = camera;
      sensor_ = &sensor;
      std::swap(buffers_, probe_buffers_);
      countOcclusion(num_objects);
      sensor_->startEpisode(seed);
      observeThroughSensor();
      observation_.instance = buffers_.instance;
      observation_.amodal_bits = buffers_.amodal_bits;
      rule_.start(occlusion);
      info_.occlusion = std::move(occlusion);
      info_.pose = start_pose;
      info_.world_from_optical = world_from_optical;
      info_.intrinsics = renderer_->intrinsics();
      info_.last_action = Action{};
      info_.step_index = rule_.stepIndex();
      has_episode_ = true;

      StepResult result;
      result.observation = &observation_;
      result.info = info_;
      return result;
    }
  } catch (...) {
    restore();
    throw;
  }
  restore();
  std::ostringstream message;
  message << "no scene with occlusion at the start view in " << num_attempts << " draws from seed "
          << seed << " (preset " << toString(preset)
          << "); raise max_scene_attempts or choose other objects";
  throw SceneGenerationError(message.str());
}

SphericalCamera Environment::cameraFor(const SceneSetup& setup, const Room* room) const {
  const double limit = options_.elevation_limit_rad;
  if (!room) return SphericalCamera(setup.radius_m, limit);
  // In the scene's own units the camera stands at options_.radius_m (roomFor).
  const double above_floor =
      lowestElevationAbove(*room, options_.radius_m, options_.world.floor_clearance_m);
  return SphericalCamera(setup.radius_m, std::clamp(above_floor, -limit, limit), limit);
}

std::unique_ptr<Room> Environment::roomFor(Scene& scene, const SceneSetup& setup,
                                           RandomSource& random) {
  if (setup.world != "room") return nullptr;
  WorldOptions world = options_.world;
  world.world = setup.world;
  const double floor_height = standOnFloor(scene);
  // The room is drawn in the scene's own units, where the camera stands at options_.radius_m.
  return std::make_unique<Room>(
      generateRoom(scene, floor_height, options_.radius_m, world, *library_, random));
}

StepResult Environment::step(const Action& action) {
  if (!has_episode_) throw InvalidStateError("step() before any reset(): call reset first");
  rule_.requireStep();
  const Action move = cameraMoveFor(action, options_.step_size_rad, options_.normalize_action);

  info_.pose = camera_.moved(info_.pose, move.d_azimuth_rad, move.d_elevation_rad);
  info_.world_from_optical = camera_.worldFromOptical(info_.pose);
  info_.last_action = action;
  renderCurrent();
  const StepVerdict verdict = rule_.step(info_.occlusion.total_pixels);
  info_.step_index = rule_.stepIndex();

  StepResult result;
  result.observation = &observation_;
  result.reward = verdict.reward;
  result.terminated = verdict.terminated;
  result.truncated = verdict.truncated;
  result.info = info_;
  return result;
}

const StepInfo& Environment::viewFrom(const SphericalPose& pose) {
  if (!has_episode_) throw InvalidStateError("viewFrom() before any reset(): call reset first");
  if (!std::isfinite(pose.azimuth_rad) || !std::isfinite(pose.elevation_rad)) {
    throw InvalidArgumentError("camera pose must be finite");
  }
  info_.pose = camera_.normalized(pose);
  info_.world_from_optical = camera_.worldFromOptical(info_.pose);
  renderCurrent();
  return info_;
}

const StepInfo& Environment::moveOutsideEpisode(const Action& action) {
  if (!has_episode_) throw InvalidStateError("moveOutsideEpisode() before any reset()");
  const Action move = cameraMoveFor(action, options_.step_size_rad, options_.normalize_action);
  viewFrom(camera_.moved(info_.pose, move.d_azimuth_rad, move.d_elevation_rad));
  ++info_.step_index;
  info_.last_action = action;
  return info_;
}

void Environment::renderCurrent() {
  renderer_->render(info_.world_from_optical, buffers_);
  info_.occlusion = countOcclusion(static_cast<int>(scene_.objects.size()));
  if (!sensor_->isIdeal()) sensor_->apply(buffers_.rgb, buffers_.depth, renderer_->intrinsics());
}

void Environment::observeThroughSensor() {
  if (sensor_->isIdeal()) {
    observation_.rgb = buffers_.rgb;
    observation_.depth = buffers_.depth;
    return;
  }
  sensor_->apply(buffers_.rgb, buffers_.depth, renderer_->intrinsics());
  observation_.rgb = sensor_->rgb();
  observation_.depth = sensor_->depth();
}

OcclusionStats Environment::countOcclusion(int num_objects) {
  // Silhouettes lie inside the footprint; the mask's last non-zero pixels inside the last one.
  const cv::Rect region = buffers_.target_footprint | occlusion_mask_region_;
  OcclusionStats occlusion =
      computeOcclusion(buffers_.amodal_bits, num_objects, region, &observation_.occlusion_mask);
  occlusion_mask_region_ = buffers_.target_footprint;
  return occlusion;
}

const RenderBuffers& Environment::renderAt(const SphericalPose& pose) {
  if (!has_episode_) throw InvalidStateError("renderAt() before any reset(): call reset first");
  if (!std::isfinite(pose.azimuth_rad) || !std::isfinite(pose.elevation_rad)) {
    throw InvalidArgumentError("pose must be finite");
  }
  renderer_->render(camera_.worldFromOptical(camera_.normalized(pose)), probe_buffers_);
  return probe_buffers_;
}

}  // namespace occlusion_env
