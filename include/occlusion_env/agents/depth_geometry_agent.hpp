// The depth-geometry agent: no network, no simulator. It fuses the depth of every view of the
// episode into voxels in the sphere's frame (leaving out floors, walls and ceilings), splits them
// into objects by the gaps between them, and plans on the rig's own lattice of moves: the nearest
// pose from which no two objects' voxels project onto the same pixel, one step towards it per
// view (doc/AGENTS.md, "The depth-geometry agent").
#pragma once

#include <cmath>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "occlusion_env/agents/agent_registry.hpp"
#include "occlusion_env/occlusion/bounding_surfaces.hpp"

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
  /// Floors, walls and ceilings are not fused: in a room the floor would join every object into
  /// one. Each view's bounding surfaces (occlusion/bounding_surfaces.hpp: large planes with
  /// nothing seen behind them, and the sphere's centre in front of them) are snapped level or
  /// upright (those tilted more than 10 deg from both are not used) and kept for the episode;
  /// nothing within their measured spread of them, or behind them, is fused from any view.
  bool skip_bounding_surfaces = true;
  /// The plane search. Its tolerance grows with depth 5 times faster than the camera bridge's
  /// (0.02 z^2 [m] against 0.004): the D435 model scatters a wall facing it by 0.0037 z^2 (1
  /// sigma: 13 cm at 6 m), so with the bridge's tolerance about a tenth of a far wall's points
  /// lay "behind" it and it was not taken for a bound (chosen on validation scenes in a room:
  /// doc/AGENTS.md, "The depth-geometry agent").
  BoundingSurfaceOptions bounding_surfaces = [] {
    BoundingSurfaceOptions options;
    options.tolerance_per_m2 = 0.02;
    return options;
  }();

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
  // The elevations the rig was seen to reach [rad]: a move that came short of the elevation asked
  // for met a limit (a room's floor, an arm's joint), and poses beyond it are not planned for.
  double lowest_elevation_rad_ = -M_PI / 2;
  double highest_elevation_rad_ = M_PI / 2;
  void noteElevationLimits(const SphericalPose& pose);
  // The current objects' voxel centres in the world frame [m] and their object index.
  std::vector<Eigen::Vector3d> centres_;
  std::vector<int> object_of_;
  int objects_ = 0;
  // Per pixel of a checked pose: the pose's stamp and the objects seen there (bit k = object k).
  std::vector<std::uint32_t> pixel_stamp_;
  std::vector<std::uint32_t> pixel_objects_;
  std::uint32_t stamp_ = 0;
  // A floor or wall in the world frame: normal . p + offset_m = 0, the normal towards the
  // sphere's centre (offset_m > 0). A point lies on it within voxel_m_ + spread_per_m2 z^2 [m]
  // (z: the point's depth), the spread measured on the view that found it: 3 sigma of its
  // points' distances, sigma taken to grow with z^2 as a stereo camera's does.
  struct Bound {
    Eigen::Vector3d normal;
    double offset_m;
    double spread_per_m2;
  };
  BoundingSurfaceFinder surfaces_;
  cv::Mat on_surface_;         // the last view's bounding-surface pixels (255)
  std::vector<Bound> bounds_;  // the episode's: nothing on or behind one is fused
  // Adds the surfaces the view found (`planes`, optical frame) that are new; erases the fused
  // voxels on or behind each new one.
  void noteBounds(const std::vector<SurfacePlane>& planes, const cv::Mat& depth,
                  const CameraIntrinsics& intrinsics, const Eigen::Isometry3d& world_from_optical,
                  double radius);
  // The view's bounding-surface pixels (on_surface_), each with its nearest of `planes`:
  // scratch_.surface_points[plane] = (world x, y, z [m], depth [m]).
  void collectSurfacePoints(const std::vector<SurfacePlane>& planes, const cv::Mat& depth,
                            const CameraIntrinsics& intrinsics,
                            const Eigen::Isometry3d& world_from_optical);
  // Whether `world` [m], seen at depth `z_m`, lies on or behind a bound.
  bool onOrBehindBound(const Eigen::Vector3d& world, double z_m) const;
  std::vector<std::uint8_t> grid_;    // scratch of splitIntoObjects()
  std::vector<std::int32_t> labels_;  // scratch of splitIntoObjects()
  struct Scratch {  // splitIntoObjects()' buffers, kept between views to reuse their memory
    std::vector<std::uint64_t> keys;
    std::vector<Eigen::Vector3i> cells, stack;
    std::vector<std::uint8_t> line;
    std::vector<int> voxels_per_label, label_of_voxel, order, object_of_label;
    std::vector<std::vector<Eigen::Vector4d>> surface_points;  // noteBounds(): x, y, z, depth
    std::vector<double> values;
  } scratch_;
  Action last_move_{1.0, 0.0};
  DepthGeometryPlan plan_;
};

AgentEntry depthGeometryAgentEntry();

}  // namespace occlusion_env
