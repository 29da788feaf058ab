// Scene generation as in Section 3 of the paper, with the original code's distances.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "occlusion_env/common/random.hpp"
#include "occlusion_env/scene/model_split.hpp"
#include "occlusion_env/scene/object_library.hpp"

namespace occlusion_env {

/// One object placed in the world frame.
struct SceneObject {
  std::shared_ptr<const ObjectModel> model;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  // of the bounding-box centre [m]
};

struct Scene {
  std::vector<SceneObject> objects;
  /// World metres per metre of the objects' models and positions: the renderer draws object k
  /// at scale * position_m, scale times its size (camera randomisation, env/scene_setup.hpp).
  double scale = 1.0;
};

/// Canned scenes. kTwoChairs / kTwoTables: two copies of one model, the second 2 m nearer the
/// camera's reference direction (+x), no sideways offset (the paper's Figure 4/5 scenes).
enum class ScenePreset { kRandom, kTwoChairs, kTwoTables };

/// "random" | "two_chairs" | "two_tables"; throws InvalidArgumentError otherwise.
ScenePreset parseScenePreset(const std::string& text);
std::string toString(ScenePreset preset);

struct SceneOptions {
  int num_objects = 3;           // 1..kMaxSceneObjects
  double depth_spacing_m = 1.0;  // object k sits k * spacing towards +x (the azimuth-0 camera)
  double lateral_sigma_m = 1.0;  // sideways offset x ~ N(0, sigma); odd k get +x, even k get -x
  std::vector<std::string> categories;  // draw only from these (empty: any)
  std::vector<std::string> object_ids;  // use exactly these, in order (overrides categories)
  /// Draw only models of this split (scene/model_split.hpp); explicit object_ids must lie in it.
  ModelSplit model_split = ModelSplit::kAll;
};

/// Draws a scene from `random`. Object 0 at the origin; object k (k >= 1) at
/// (k * spacing, +/- x, 0), where the sign alternates (+x for k = 1, -x for k = 2, ...) and x is
/// drawn once per scene, so objects 1 and 2 sit on opposite sides as in the paper.
/// Throws InvalidArgumentError for an unknown id or category, or a bad object count.
Scene generateScene(ObjectLibrary& library, const SceneOptions& options, ScenePreset preset,
                    RandomSource& random);

}  // namespace occlusion_env
