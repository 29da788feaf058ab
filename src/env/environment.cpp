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

std::unique_ptr<Renderer> rendererFor(const EnvironmentOptions& options) {
  const CameraIntrinsics intrinsics =
      CameraIntrinsics::fromFieldOfView(options.width, options.height, options.field_of_view_rad);
  std::unique_ptr<Renderer> renderer = options.renderer_factory
                                           ? options.renderer_factory(intrinsics, options.renderer)
                                           : makeOsMesaRenderer(intrinsics, options.renderer);
  if (!renderer) throw InvalidArgumentError("the renderer factory made no renderer");
  return renderer;
}

std::shared_ptr<ObjectLibrary> libraryFor(const EnvironmentOptions& options) {
  std::shared_ptr<const ObjectCatalog> catalog = makeCatalog(options.catalog);
  return std::make_shared<ObjectLibrary>(std::move(catalog), options.lod_triangle_budget);
}

}  // namespace

void EnvironmentOptions::validate() const {
  environmentOptionTable().check(*this);
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
  sensor.validate();
  world.validate();
}

Environment::Environment(const EnvironmentOptions& options, std::shared_ptr<ObjectLibrary> library)
    : options_((options.validate(), options)),
      camera_(options.radius_m, options.elevation_limit_rad),
      library_(library ? std::move(library) : libraryFor(options)),
      renderer_(rendererFor(options)),
      sensor_(options.sensor),
      reward_(options.reward) {}

Environment::~Environment() = default;

GradientResult Environment::occlusionGradient() {
  if (!gradient_) gradient_ = makeOcclusionGradient(options_.gradient_method, options_.gradient);
  return gradient_->compute(*this);
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
    placed.push_back(mesh);
  }
  renderer_->setScene(placed);
  if (room) renderer_->setBackground(room->background());
}

StepResult Environment::reset(std::uint64_t seed, const ResetOptions& overrides) {
  const ScenePreset preset = parseScenePreset(overrides.preset.value_or(options_.preset));
  SceneOptions scene_options = options_.scene;
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
      !(std::abs(*overrides.start_elevation_rad) <= options_.elevation_limit_rad)) {
    throw InvalidArgumentError("start elevation must lie within +/- the elevation limit");
  }

  RandomSource random(seed);
  const double azimuth_range = options_.start_azimuth_range_rad;
  const double drawn_azimuth = random.uniform(-azimuth_range, azimuth_range);
  const SphericalPose start_pose =
      camera_.normalized({overrides.start_azimuth_rad.value_or(drawn_azimuth),
                          overrides.start_elevation_rad.value_or(options_.start_elevation_rad)});
  const Eigen::Isometry3d world_from_optical = camera_.worldFromOptical(start_pose);

  // Draw scenes until the start view shows occlusion. Candidates render into the probe buffers,
  // so the current episode stays intact until one is accepted.
  const int num_attempts = options_.max_scene_attempts;
  try {
    for (int attempt = 0; attempt < num_attempts; ++attempt) {
      Scene candidate = generateScene(*library_, scene_options, preset, random);
      std::unique_ptr<Room> candidate_room;
      if (options_.world.isRoom()) {
        const double floor_height = standOnFloor(candidate);
        candidate_room = std::make_unique<Room>(generateRoom(
            candidate, floor_height, options_.radius_m, options_.world, *library_, random));
      }
      placeScene(candidate, candidate_room.get());
      renderer_->render(world_from_optical, probe_buffers_);
      const int num_objects = static_cast<int>(candidate.objects.size());
      OcclusionStats occlusion = computeOcclusion(probe_buffers_.amodal_bits, num_objects,
                                                  probe_buffers_.target_footprint);
      if (reward_.solved(occlusion.total_pixels)) continue;  // the threshold only, not Z

      scene_ = std::move(candidate);
      room_ = std::move(candidate_room);
      std::swap(buffers_, probe_buffers_);
      countOcclusion(num_objects);
      sensor_.startEpisode(seed);
      observeThroughSensor();
      observation_.instance = buffers_.instance;
      observation_.amodal_bits = buffers_.amodal_bits;
      reward_.startEpisode(occlusion);
      info_.occlusion = std::move(occlusion);
      info_.pose = start_pose;
      info_.world_from_optical = world_from_optical;
      info_.step_index = 0;
      has_episode_ = true;
      episode_over_ = false;

      StepResult result;
      result.observation = &observation_;
      result.info = info_;
      return result;
    }
  } catch (...) {
    if (has_episode_)
      placeScene(scene_, room_.get());  // the renderer draws the current episode again
    throw;
  }
  if (has_episode_) placeScene(scene_, room_.get());
  std::ostringstream message;
  message << "no scene with occlusion at the start view in " << num_attempts << " draws from seed "
          << seed << " (preset " << toString(preset)
          << "); raise max_scene_attempts or choose other objects";
  throw SceneGenerationError(message.str());
}

StepResult Environment::step(const Action& action) {
  if (!has_episode_) throw InvalidStateError("step() before any reset(): call reset first");
  if (episode_over_) {
    throw InvalidStateError("the episode has ended (terminated or truncated): call reset");
  }
  const Action move = cameraMoveFor(action, options_.step_size_rad, options_.normalize_action);

  const std::int64_t previous = info_.occlusion.total_pixels;
  info_.pose = camera_.moved(info_.pose, move.d_azimuth_rad, move.d_elevation_rad);
  info_.world_from_optical = camera_.worldFromOptical(info_.pose);
  renderCurrent();
  ++info_.step_index;

  StepResult result;
  result.observation = &observation_;
  result.reward = reward_(previous, info_.occlusion.total_pixels);
  result.terminated = reward_.solved(info_.occlusion.total_pixels);
  result.truncated = !result.terminated && info_.step_index >= options_.max_steps;
  episode_over_ = result.terminated || result.truncated;
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

void Environment::renderCurrent() {
  renderer_->render(info_.world_from_optical, buffers_);
  info_.occlusion = countOcclusion(static_cast<int>(scene_.objects.size()));
  if (!sensor_.isIdeal()) sensor_.apply(buffers_.rgb, buffers_.depth, renderer_->intrinsics());
}

void Environment::observeThroughSensor() {
  if (sensor_.isIdeal()) {
    observation_.rgb = buffers_.rgb;
    observation_.depth = buffers_.depth;
    return;
  }
  sensor_.apply(buffers_.rgb, buffers_.depth, renderer_->intrinsics());
  observation_.rgb = sensor_.rgb();
  observation_.depth = sensor_.depth();
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
