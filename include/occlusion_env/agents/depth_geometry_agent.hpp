// The depth-geometry agent: no network, no simulator. It fuses the depth of every view of the
// episode into voxels in the sphere's frame, splits them into objects by the gaps between them,
// and plans on the rig's own lattice of moves: the nearest pose from which no two objects' voxels
// project onto the same pixel, one step towards it per view (doc/AGENTS.md, "The depth-geometry
// agent").
#pragma once

#include <cstdint>
#include <unordered_set>
#include <vector>

#include <Eigen/Core>

#include "occlusion_env/agents/agent_registry.hpp"

namespace occlusion_env {

struct DepthGeometryOptions {
  /// Voxel edge as a fraction of the sphere's radius (the camera's distance from the centre):
  /// 0.005 = 2 cm at 4 m, so that the agent sees a scene scaled with its radius alike.
  double voxel_fraction = 0.005;
  /// Occupied voxels whose cubes grown by this many voxels touch (within 2 n + 1 voxels of each
  /// other along every axis: 30 cm at 4 m) belong to one object. Fewer splits an object whose
  /// middle another hides into pieces that then "hide" each other; more joins objects that
  /// stand near each other. 7 was chosen on validation scenes among 3 and 5-9
  /// (doc/AGENTS.md, "The depth-geometry agent").
  int join_voxels = 7;
  /// Objects of fewer voxels are dropped (a stray edge pixel, a far speck).
  int min_object_voxels = 30;

  /// The planning lattice's spacing and the step the rig makes [rad]: the environment's step.
  double step_size_rad = 0.05;
  /// Poses farther than this many steps are not checked.
  double search_radius_steps = 14.0;
  /// The rig's elevation limit [rad]: poses beyond it are not checked.
  double elevation_limit_rad = 1.3962634016;
};

/// What the agent saw and chose at its last act(), for tests and diagnostics.
struct DepthGeometryPlan {
  int voxels = 0;                 // fused so far, within the sphere
  int objects = 0;                // after the join and the size filter
  bool found_clear_pose = false;  // a checked pose shows no overlap
  int overlap_px = 0;             // at the chosen target (0 when found_clear_pose)
  double target_d_azimuth_rad = 0.0;
  double target_d_elevation_rad = 0.0;
};

/// Reads only what a camera on a rig gives (depth, intrinsics, the optical frame in the sphere's
/// frame). Needs finite positive focal lengths and the camera away from the sphere's centre;
/// act() throws InvalidArgumentError otherwise.
class DepthGeometryAgent : public Agent {
 public:
  /// Throws InvalidArgumentError for options out of range.
  explicit DepthGeometryAgent(DepthGeometryOptions options = {});
  void reset(std::uint64_t seed) override;
  Action act(const RigObservation& observation) override;

  const DepthGeometryPlan& lastPlan() const { return plan_; }

 private:
  struct LatticeOffset {
    double distance_steps;
    int azimuth_steps;
    int elevation_steps;
  };
  void integrate(const RigObservation& observation);
  void splitIntoObjects();
  // Labels the 26-connected parts of the grown grid (grid_, `size` cells) that hold the occupied
  // voxels (scratch_.cells): labels_ per cell, scratch_.voxels_per_label and label_of_voxel.
  void labelGrownParts(const Eigen::Vector3i& size);
  // Pixels covered by two or more objects when the camera sits at `pose`; stops counting once
  // the count reaches `stop_at`.
  int overlapPixels(const Eigen::Isometry3d& world_from_optical, const CameraIntrinsics& intrinsics,
                    int stop_at);

  DepthGeometryOptions options_;
  std::vector<LatticeOffset> lattice_;  // nearest first
  double voxel_m_ = 0.0;                // fixed at an episode's first view
  std::unordered_set<std::uint64_t> occupied_;
  std::vector<SphericalPose> visited_;  // the episode's views so far
  // The current objects' voxel centres in the world frame [m] and their object index.
  std::vector<Eigen::Vector3d> centres_;
  std::vector<int> object_of_;
  int objects_ = 0;
  // Per pixel of a checked pose: the pose's stamp and the objects seen there (bit k = object k).
  std::vector<std::uint32_t> pixel_stamp_;
  std::vector<std::uint32_t> pixel_objects_;
  std::uint32_t stamp_ = 0;
  std::vector<std::uint8_t> grid_;    // scratch of splitIntoObjects()
  std::vector<std::int32_t> labels_;  // scratch of splitIntoObjects()
  struct Scratch {  // splitIntoObjects()' buffers, kept between views to reuse their memory
    std::vector<std::uint64_t> keys;
    std::vector<Eigen::Vector3i> cells, stack;
    std::vector<std::uint8_t> line;
    std::vector<int> voxels_per_label, label_of_voxel, order, object_of_label;
  } scratch_;
  Action last_move_{1.0, 0.0};
  DepthGeometryPlan plan_;
};

AgentEntry depthGeometryAgentEntry();

}  // namespace occlusion_env
