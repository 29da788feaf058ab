// Rendering interface: one call gives colour, metric depth, the visible-instance mask, each
// object's amodal silhouette and each object's own front depth. OSMesa implements it; an EGL
// back end can follow behind the same interface.
#pragma once

#include <Eigen/Geometry>
#include <limits>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include <functional>

#include "occlusion_env/common/limits.hpp"
#include "occlusion_env/geometry/camera.hpp"
#include "occlusion_env/scene/mesh.hpp"

namespace occlusion_env {

/// A mesh placed in the world. The mesh must outlive the renderer's use of it (until the next
/// setScene()).
struct PlacedMesh {
  const Mesh* mesh = nullptr;
  /// Rigid, or rigid times a uniform scale (a scaled scene, Scene::scale).
  Eigen::Affine3d world_from_object = Eigen::Affine3d::Identity();
};

/// Everything one render produces. Allocated on the first render; later renders write into the
/// same buffers (no allocation on the hot path), so copy (clone) what must outlive the next call.
struct RenderBuffers {
  cv::Mat rgb;          // CV_8UC3, RGB order (rgb8)
  cv::Mat depth;        // CV_32FC1, [m] along the optical axis, NaN where nothing is hit (REP 118)
  cv::Mat instance;     // CV_8UC1, 0 = background, k + 1 = object k is the nearest surface
  cv::Mat amodal_bits;  // CV_8UC1, bit k set where object k covers the pixel, hidden or not
  std::vector<cv::Mat> object_depth;  // per object, CV_32FC1: [m] of its front surface alone,
                                      // +inf where the object does not cover the pixel
  /// The union of the objects' footprints in the last render [px] (the whole image when the scene
  /// has a background, SceneBackground): outside it every image holds
  /// the background (rgb 0, depth NaN, instance 0, amodal bits 0, object depths +inf), so per-pixel
  /// work may stay inside. Unbounded until the first render. The renderer rewrites only these
  /// pixels and those of the new footprint, so do not write into the images (clone them) and do
  /// not render into two RenderBuffers that share pixels.
  cv::Rect footprint{0, 0, std::numeric_limits<int>::max(), std::numeric_limits<int>::max()};
  /// The union of the objects' footprints in the last render [px], background or not: outside it
  /// instance, amodal_bits and object_depth hold the background (0, 0, +inf). Equals `footprint`
  /// for a scene without a background. Unbounded until the first render.
  cv::Rect target_footprint{0, 0, std::numeric_limits<int>::max(), std::numeric_limits<int>::max()};
};

/// The light of a scene: ambient + diffuse * colour * max(n . l, 0) times each surface's colour.
struct SceneLighting {
  /// true: today's light fixed to the camera (back and up in the optical frame); to_light_world
  /// is unused then.
  bool headlight = true;
  Eigen::Vector3d to_light_world{0.0, 0.0, 1.0};  // unit vector towards the light
  Eigen::Vector3f color{1.0f, 1.0f, 1.0f};        // of the diffuse light
  float ambient = 0.3f;
  float diffuse = 0.7f;
};

/// A flat rectangle of cells u x v, each of one colour (floor tiles, wall panels), in the world
/// frame: cell (i, j) spans origin + [i, i + 1] step_u + [j, j + 1] step_v. Drawn one-sided, seen
/// only from the side step_u x step_v points to. A renderer can draw it as one quad whatever the
/// number of cells.
struct TiledSurface {
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();   // [m]
  Eigen::Vector3f step_u = Eigen::Vector3f::UnitX();  // [m] one cell along u
  Eigen::Vector3f step_v = Eigen::Vector3f::UnitY();  // [m] one cell along v
  int cells_u = 1;
  int cells_v = 1;
  std::vector<Eigen::Vector3f> colors;  // linear RGB in [0, 1], cell (i, j) at j * cells_u + i
};

/// What surrounds the target objects (a room): drawn into colour, depth and the visible instance
/// map (as 0, background), never into the amodal silhouettes or the objects' own depths, so the
/// occlusion count sees only the targets. Meshes must outlive the renderer's use of them.
struct SceneBackground {
  /// Consistently wound surfaces, drawn one-sided: only from the side whose triangles run
  /// counter-clockwise as seen from it. A camera behind such a surface sees through it.
  std::vector<PlacedMesh> one_sided;
  std::vector<TiledSurface> tiled;    // one-sided too (floor, walls, ceiling)
  std::vector<PlacedMesh> two_sided;  // other meshes (background clutter), seen from both sides
  SceneLighting lighting;
};

class Renderer {
 public:
  virtual ~Renderer() = default;

  /// Uploads the scene's meshes (at most kMaxSceneObjects); called on reset, not on step.
  /// Throws InvalidArgumentError for too many objects or a null mesh.
  virtual void setScene(const std::vector<PlacedMesh>& objects) = 0;

  /// Sets what surrounds the objects and the light; called on reset, after setScene(). An empty
  /// background and the default lighting give the images of a renderer that never had one. The
  /// default implementation accepts only that.
  virtual void setBackground(const SceneBackground& background);

  /// Renders the current scene seen from `world_from_optical` into `out`.
  virtual void render(const Eigen::Isometry3d& world_from_optical, RenderBuffers& out) = 0;

  virtual const CameraIntrinsics& intrinsics() const = 0;
  virtual std::string name() const = 0;
};

/// Options every renderer back end understands.
struct RendererOptions {
  /// Rasteriser threads besides the calling one. 0 rasterises on the calling thread: on 2 cores a
  /// step ran 1.2-1.7x faster that way at 128-512 px, and one environment per core can then run in
  /// parallel. (llvmpipe reads this once per process; see osmesa_renderer.hpp.)
  int rasterizer_threads = 0;
};

/// Makes the renderer of an environment, on the calling thread (which then owns its GL context).
using RendererFactory =
    std::function<std::unique_ptr<Renderer>(const CameraIntrinsics&, const RendererOptions&)>;

}  // namespace occlusion_env
