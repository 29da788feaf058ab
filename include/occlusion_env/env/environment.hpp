// The in-process simulator: the EnvironmentInterface on the core's scenes, renderer, occlusion
// count and reward (Gym-style: reset(seed) -> StepResult, step(Action) -> StepResult).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/env/environment_interface.hpp"
#include "occlusion_env/env/episode_rule.hpp"
#include "occlusion_env/env/room.hpp"
#include "occlusion_env/env/scene_setup.hpp"
#include "occlusion_env/geometry/camera.hpp"
#include "occlusion_env/occlusion/occlusion.hpp"
#include "occlusion_env/occlusion/occlusion_gradient.hpp"
#include "occlusion_env/occlusion/reward.hpp"
#include "occlusion_env/render/renderer.hpp"
#include "occlusion_env/scene/object_library.hpp"
#include "occlusion_env/scene/scene.hpp"
#include "occlusion_env/sensor/camera_sensor.hpp"

namespace occlusion_env {

/// Every option of the environment. Names, ranges, units and meanings are declared once, in
/// environmentOptionTable(); config/sim.yaml and doc/USER_GUIDE.md are tested against it.
struct EnvironmentOptions {
  // Camera.
  int width = 256;                                 // [px], 64..1024
  int height = 256;                                // [px], 64..1024
  double field_of_view_rad = 1.0471975512;         // horizontal, 60 deg
  double radius_m = 4.0;                           // sphere radius
  double elevation_limit_rad = 1.3962634016;       // +/- 80 deg
  double start_azimuth_range_rad = 0.09817477042;  // start azimuth ~ U(-r, r), r = pi/32
  double start_elevation_rad = 0.0;
  /// Per-scene draws of radius, field of view, resolution and intrinsics (off: the above).
  CameraRandomization camera_randomization;

  // Objects.
  CatalogOptions catalog;
  std::size_t lod_triangle_budget = 5000;  // per object; 0 renders full meshes
  SceneOptions scene;
  std::string preset = "random";  // random | two_chairs | two_tables
  int max_scene_attempts = 20;    // re-draws until the start view shows occlusion

  // Actions and episodes.
  bool normalize_action = true;  // true: every step moves exactly step_size_rad along the action
  double step_size_rad =
      0.05;            // unit step (the original code's); also the clip when not normalised
  int max_steps = 50;  // truncation
  RewardOptions reward;

  // Rendering and the simulator's own occlusion gradient.
  RendererOptions renderer;
  RendererFactory renderer_factory;          // empty: OSMesa (render/osmesa_renderer.hpp)
  OcclusionGradientOptions gradient;         // of occlusionGradient()
  std::string gradient_method = "analytic";  // of occlusionGradient(): analytic | finite_difference

  // The world around the targets (env/room.hpp): void (the paper's), room, or random (one of
  // them drawn per scene, env/scene_setup.hpp).
  WorldOptions world;

  // What the camera reports (sensor/camera_sensor.hpp): only the observation goes through it.
  // depth_sensor random: one of the sensors drawn per scene.
  SensorOptions sensor;

  /// Throws InvalidArgumentError naming the first bad option: the table's ranges and choices,
  /// then the rules between options.
  void validate() const;
};

/// The declared options of EnvironmentOptions, by their ROS parameter names (config/sim.yaml).
const OptionTable<EnvironmentOptions>& environmentOptionTable();

class Environment : public EnvironmentInterface, public RenderedView {
 public:
  /// Validates the options and creates the renderer on the calling thread (which must then make
  /// every call). `library` may be shared between environments; nullptr builds one from options.
  explicit Environment(const EnvironmentOptions& options,
                       std::shared_ptr<ObjectLibrary> library = nullptr);
  ~Environment() override;
  Environment(const Environment&) = delete;
  Environment& operator=(const Environment&) = delete;

  /// Draws a new scene from `seed` and renders the start view. On any error the previous episode
  /// (if any) is left as it was.
  StepResult reset(std::uint64_t seed, const ResetOptions& overrides = {}) override;

  /// Moves the camera. Throws InvalidStateError before the first reset and InvalidArgumentError
  /// for a non-finite action; in both cases the state is unchanged. A zero action is a no-op move
  /// that still counts as a step.
  StepResult step(const Action& action) override;

  /// Puts the camera at `pose` (normalized) and renders the view there, outside the episode's
  /// steps: no reward, step count or end. How the simulator stands in for a real camera that a
  /// robot moves (ros/stand_in_camera.hpp). Throws InvalidStateError before the first reset and
  /// InvalidArgumentError for a non-finite pose, leaving the view as it was.
  const StepInfo& viewFrom(const SphericalPose& pose);

  /// Moves the camera by `action` as step() would and renders the view there (viewFrom), outside
  /// the episode: no reward or end, the rule's step count unchanged. Counts the move in
  /// info().step_index and records it as info().last_action. How a camera moves on after its
  /// episode has ended (occlusion_bridge_calibration, occlusion_dagger --moves-past-clear).
  /// Throws as step() and viewFrom() do.
  const StepInfo& moveOutsideEpisode(const Action& action);

  /// The gradient of the current view by options().gradient_method, with options().gradient.
  bool hasOcclusionGradient() const override { return true; }
  GradientResult occlusionGradient() override;
  /// Views of the current view's masks and info().occlusion.
  bool hasPrivilegedObservation() const override { return true; }
  PrivilegedObservation privilegedObservation() override;
  Environment* simulation() override { return this; }
  std::string describe() const override { return "in-process simulator"; }

  /// Renders the current scene from `pose` without changing the episode (for finite
  /// differences). The buffers are separate from the observation's.
  const RenderBuffers& renderAt(const SphericalPose& pose) override;

  bool hasEpisode() const { return has_episode_; }
  const EnvironmentOptions& options() const { return options_; }
  const CameraIntrinsics& intrinsics() const override;
  const SphericalCamera& camera() const override { return camera_; }
  const Scene& scene() const { return scene_; }
  /// The current episode's room; nullptr in the void world.
  const Room* room() const { return room_.get(); }
  const StepInfo& info() const { return info_; }
  const Observation& observation() const { return observation_; }
  /// The ideal buffers the observation is made from, including each object's own depth (the
  /// occlusion count and gradients read these, never the sensor's output).
  const RenderBuffers& renderBuffers() const override { return buffers_; }
  /// The current episode's sensor (before the first reset: the options' or ideal).
  const CameraSensor& sensor() const { return *sensor_; }
  /// The current episode's world, sensor and camera (drawn per scene where the options say so).
  const SceneSetup& sceneSetup() const { return setup_; }
  const RewardFunction& reward() const { return rule_.reward(); }
  /// The episode's steps, reward and end (env/episode_rule.hpp: the camera bridge's rule too).
  const EpisodeRule& episodeRule() const { return rule_; }
  ObjectLibrary& library() { return *library_; }

  // RenderedView (the occlusion gradients' view of the current episode).
  bool hasView() const override { return has_episode_; }
  int numObjects() const override { return static_cast<int>(scene_.objects.size()); }
  SphericalPose pose() const override { return info_.pose; }

 private:
  /// Gives the renderer the scene's targets and, in a room, the room around them (both scaled
  /// by scene.scale).
  void placeScene(const Scene& scene, const Room* room);
  /// The room of a scene in `setup`'s room world (the scene then stands on its floor), drawn
  /// from `random`; nullptr in the void.
  std::unique_ptr<Room> roomFor(Scene& scene, const SceneSetup& setup, RandomSource& random);
  /// The camera of a scene in `setup`: within +/- the elevation limit, and in a room never lower
  /// than floor_clearance above its floor.
  SphericalCamera cameraFor(const SceneSetup& setup, const Room* room) const;
  /// The sensor named `depth_sensor`, made on first use with the options' parameters.
  CameraSensor& sensorFor(const std::string& depth_sensor);
  void renderCurrent();
  /// Points the observation's rgb and depth at what the camera sensor makes of buffers_.
  void observeThroughSensor();
  /// Counts the occlusion in buffers_ and rewrites observation_.occlusion_mask to match.
  OcclusionStats countOcclusion(int num_objects);

  EnvironmentOptions options_;
  SphericalCamera camera_;  // the current episode's (its radius may be drawn per scene)
  std::shared_ptr<ObjectLibrary> library_;
  std::unique_ptr<Renderer> renderer_;
  std::vector<std::unique_ptr<CameraSensor>> sensors_;  // by depthSensorNames(), made on use
  CameraSensor* sensor_ = nullptr;                      // the current episode's
  SceneSetup setup_;                                    // the current episode's
  std::unique_ptr<OcclusionGradient> gradient_;         // made on the first occlusionGradient()
  EpisodeRule rule_;  // the simulator's: clear on the first view at or below the threshold
  Scene scene_;
  std::unique_ptr<Room> room_;  // of scene_; null in the void world
  RenderBuffers buffers_;
  RenderBuffers probe_buffers_;
  Observation observation_;
  cv::Rect occlusion_mask_region_;  // where observation_.occlusion_mask may be non-zero [px]
  StepInfo info_;
  bool has_episode_ = false;
};

}  // namespace occlusion_env
