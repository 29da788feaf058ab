// The seam every agent and every camera plugs into: reset(seed) and step(action), and what an
// agent may read of a view (RigObservation; PrivilegedObservation only for the reference agents
// that declare the need, agents/agent_registry.hpp). Implemented by the simulator (Environment), by
// the camera bridge's logic on a camera rig (CameraEnvironment, env/camera_environment.hpp), both
// on one episode rule (env/episode_rule.hpp), and by a client of their ROS services
// (ros/environment_client.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "occlusion_env/geometry/camera.hpp"
#include "occlusion_env/occlusion/occlusion.hpp"
#include "occlusion_env/occlusion/occlusion_gradient.hpp"

namespace occlusion_env {

class Environment;

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

/// The move an environment makes for `action` (doc/CONVENTIONS.md, "Actions"): scaled to length
/// `step_size_rad` when `normalize` or when longer, else as given; a zero action stays zero.
/// Throws InvalidArgumentError for a non-finite action. Shared by the simulator and the camera
/// bridge, so both move the camera alike.
Action cameraMoveFor(const Action& action, double step_size_rad, bool normalize);

/// What the environment shows of a view, for its users (nodes, Python, datasets, reports): the
/// camera's images and, from a simulator, its masks. Agents see it split by type (RigObservation,
/// PrivilegedObservation below). The images are views of the environment's buffers, valid until
/// the next reset() or step(): clone them to keep them. A remote environment may leave
/// amodal_bits empty.
struct Observation {
  cv::Mat rgb;             // CV_8UC3 rgb8
  cv::Mat depth;           // CV_32FC1 [m], NaN where nothing is hit
  cv::Mat instance;        // CV_8UC1, 0 background, k + 1 = object k
  cv::Mat amodal_bits;     // CV_8UC1, bit k = object k's full silhouette
  cv::Mat occlusion_mask;  // CV_8UC1, 255 where two or more silhouettes overlap
};

struct StepInfo {
  OcclusionStats occlusion;
  OcclusionSource occlusion_source = OcclusionSource::kGroundTruth;
  SphericalPose pose;
  Eigen::Isometry3d world_from_optical = Eigen::Isometry3d::Identity();
  CameraIntrinsics intrinsics;  // of the observation's images [px]
  Action last_action;           // as given to the step that led here; zero after reset
  int step_index = 0;           // 0 after reset, t after the t-th step
};

struct StepResult {
  const Observation* observation = nullptr;  // owned by the environment; see Observation
  double reward = 0.0;
  bool terminated = false;  // occlusion at or below the threshold
  bool truncated = false;   // max_steps reached without success
  StepInfo info;
};

/// What an agent receives of a view: what a camera on a rig gives, never masks or true occlusion
/// (doc/AGENTS.md, "What an agent sees"). The images are the environment's buffers (no copies),
/// valid until its next reset() or step(); the rest is copied.
struct RigObservation {
  const cv::Mat& rgb;           // CV_8UC3 rgb8
  const cv::Mat& depth;         // CV_32FC1 [m], NaN where nothing is hit
  CameraIntrinsics intrinsics;  // of rgb and depth [px]; fx = fy = 0 where the caller has none
  SphericalPose pose;           // where the rig holds the camera on its sphere [rad]
  // The optical frame in the world (sphere) frame; identity where the caller has none.
  Eigen::Isometry3d world_from_optical = Eigen::Isometry3d::Identity();
  Action last_action;  // the rig's last move as asked for; zero after reset
  int step_index = 0;  // 0 after reset, t after the t-th step
};

/// The agent's part of a view: the images of `observation`, the rest of `info`.
RigObservation rigObservationOf(const Observation& observation, const StepInfo& info);
RigObservation rigObservationOf(Observation&&, const StepInfo&) = delete;  // would dangle
/// The agent's part of `result` (its observation must be set).
RigObservation rigObservationOf(const StepResult& result);

/// The truth about a view that no camera gives: only for reference agents whose registry entry
/// declares the need (AgentNeeds::privileged_observation). Views of the environment's buffers and
/// figures, valid until its next reset() or step().
struct PrivilegedObservation {
  const cv::Mat& instance;          // CV_8UC1, 0 background, k + 1 = object k
  const cv::Mat& amodal_bits;       // CV_8UC1, bit k = object k's full silhouette
  const cv::Mat& occlusion_mask;    // CV_8UC1, 255 where two or more silhouettes overlap
  const OcclusionStats& occlusion;  // counted from the silhouettes (OcclusionSource::kGroundTruth)
};

/// Errors are the core's exception types (common/errors.hpp), whichever implementation answers:
/// InvalidArgumentError for a request it cannot accept, InvalidStateError at the wrong time, ...,
/// and EnvironmentUnavailableError when a remote environment cannot be reached. A refused request
/// leaves the episode as it was.
class EnvironmentInterface {
 public:
  virtual ~EnvironmentInterface() = default;

  /// Starts an episode on the scene drawn from `seed` and returns its first view.
  virtual StepResult reset(std::uint64_t seed, const ResetOptions& overrides = {}) = 0;

  /// Moves the camera once and returns the new view.
  virtual StepResult step(const Action& action) = 0;

  /// Whether occlusionGradient() can answer: only a simulator can (a real camera cannot).
  virtual bool hasOcclusionGradient() const { return false; }

  /// dL_s/d(azimuth, elevation) of the current view (doc/GRADIENT.md); the episode is unchanged.
  /// Throws InvalidStateError where hasOcclusionGradient() is false.
  virtual GradientResult occlusionGradient();

  /// Whether privilegedObservation() can answer: only an in-process simulator can (a real
  /// camera's occlusion is an estimate; the simulator's services do not send amodal silhouettes).
  virtual bool hasPrivilegedObservation() const { return false; }

  /// The current view's masks and true occlusion, for agents that declare the need. Throws
  /// InvalidStateError where hasPrivilegedObservation() is false or before the first reset().
  virtual PrivilegedObservation privilegedObservation();

  /// The in-process simulation behind this interface, for reference agents that read the scene
  /// (never for agents that compete); nullptr for a remote simulator or a real camera.
  virtual Environment* simulation() { return nullptr; }

  /// What answers, for messages ("in-process simulator", "ROS services /occlusion/...").
  virtual std::string describe() const = 0;
};

}  // namespace occlusion_env
