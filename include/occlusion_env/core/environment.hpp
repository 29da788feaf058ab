// The Gym-style environment: reset(seed) -> Observation, step(Action) -> StepResult.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "occlusion_env/core/camera.hpp"
#include "occlusion_env/core/object_library.hpp"
#include "occlusion_env/core/occlusion.hpp"
#include "occlusion_env/core/renderer.hpp"
#include "occlusion_env/core/reward.hpp"
#include "occlusion_env/core/scene.hpp"

namespace occlusion_env {

/// Every option of the environment, with the defaults config/sim.yaml documents.
struct EnvironmentOptions {
  // Camera.
  int width = 256;                                 // [px], 64..1024
  int height = 256;                                // [px], 64..1024
  double field_of_view_rad = 1.0471975512;         // horizontal, 60 deg
  double radius_m = 4.0;                           // sphere radius
  double elevation_limit_rad = 1.3962634016;       // +/- 80 deg
  double start_azimuth_range_rad = 0.09817477042;  // start azimuth ~ U(-r, r), r = pi/32
  double start_elevation_rad = 0.0;

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

  /// Throws InvalidArgumentError naming the first bad option.
  void validate() const;
};

/// Per-reset overrides; unset fields use the environment's options.
struct ResetOptions {
  std::optional<std::string> preset;
  std::vector<std::string> object_ids;
  std::vector<std::string> categories;
  std::optional<double> start_azimuth_rad;
  std::optional<double> start_elevation_rad;
};

/// A camera move on the sphere [rad]. Only its direction counts when actions are normalised.
struct Action {
  double d_azimuth_rad = 0.0;
  double d_elevation_rad = 0.0;
};

/// What the camera sees. The images are views of the environment's buffers, valid until the next
/// reset() or step(): clone them to keep them.
struct Observation {
  cv::Mat rgb;             // CV_8UC3 rgb8
  cv::Mat depth;           // CV_32FC1 [m], NaN where nothing is hit
  cv::Mat instance;        // CV_8UC1, 0 background, k + 1 = object k
  cv::Mat amodal_bits;     // CV_8UC1, bit k = object k's full silhouette
  cv::Mat occlusion_mask;  // CV_8UC1, 255 where two or more silhouettes overlap
};

struct StepInfo {
  OcclusionStats occlusion;
  SphericalPose pose;
  Eigen::Isometry3d world_from_optical = Eigen::Isometry3d::Identity();
  int step_index = 0;  // 0 after reset, t after the t-th step
};

struct StepResult {
  const Observation* observation = nullptr;
  double reward = 0.0;
  bool terminated = false;  // occlusion at or below the threshold
  bool truncated = false;   // max_steps reached without success
  StepInfo info;
};

class Environment {
 public:
  /// Validates the options and creates the renderer on the calling thread (which must then make
  /// every call). `library` may be shared between environments; nullptr builds one from options.
  explicit Environment(const EnvironmentOptions& options,
                       std::shared_ptr<ObjectLibrary> library = nullptr);
  ~Environment();
  Environment(const Environment&) = delete;
  Environment& operator=(const Environment&) = delete;

  /// Draws a new scene from `seed` and renders the start view. On any error the previous episode
  /// (if any) is left as it was.
  StepResult reset(std::uint64_t seed, const ResetOptions& overrides = {});

  /// Moves the camera. Throws InvalidStateError before the first reset and InvalidArgumentError
  /// for a non-finite action; in both cases the state is unchanged. A zero action is a no-op move
  /// that still counts as a step.
  StepResult step(const Action& action);

  /// Renders the current scene from `pose` without changing the episode (for finite
  /// differences). The buffers are separate from the observation's.
  const RenderBuffers& renderAt(const SphericalPose& pose);

  bool hasEpisode() const { return has_episode_; }
  const EnvironmentOptions& options() const { return options_; }
  const CameraIntrinsics& intrinsics() const;
  const SphericalCamera& camera() const { return camera_; }
  const Scene& scene() const { return scene_; }
  const StepInfo& info() const { return info_; }
  const Observation& observation() const { return observation_; }
  /// The buffers behind the current observation, including each object's own depth.
  const RenderBuffers& renderBuffers() const { return buffers_; }
  const RewardFunction& reward() const { return reward_; }
  ObjectLibrary& library() { return *library_; }

 private:
  void placeScene(const Scene& scene);
  void renderCurrent();
  /// Counts the occlusion in buffers_ and rewrites observation_.occlusion_mask to match.
  OcclusionStats countOcclusion(int num_objects);

  EnvironmentOptions options_;
  SphericalCamera camera_;
  std::shared_ptr<ObjectLibrary> library_;
  std::unique_ptr<Renderer> renderer_;
  RewardFunction reward_;
  Scene scene_;
  RenderBuffers buffers_;
  RenderBuffers probe_buffers_;
  Observation observation_;
  cv::Rect occlusion_mask_region_;  // where observation_.occlusion_mask may be non-zero [px]
  StepInfo info_;
  bool has_episode_ = false;
  bool episode_over_ = false;
};

}  // namespace occlusion_env
