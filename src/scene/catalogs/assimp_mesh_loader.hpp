// Mesh files -> Mesh through assimp, shared by the Sweet Home 3D and mesh-folder catalogues
// (private to the core library).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>

#include "occlusion_env/scene/mesh.hpp"

namespace occlusion_env {
namespace detail {

/// Returns the bytes of `path` (as normalizePath() writes it), or nullopt when there is none.
using FileReader = std::function<std::optional<std::string>(const std::string& path)>;

/// '/'-separated path without empty, "." and ".." parts; backslashes count as separators. A
/// leading '/' is kept; ".." never climbs above the first part.
std::string normalizePath(const std::string& path);

/// Loads the triangles of `path` (its bytes, and those of the materials and textures it names,
/// relative to its folder, come from `read`). Colours: the diffuse texture sampled at each vertex
/// (sRGB decoded to linear, wrapping, OBJ's v up) times the material's diffuse colour; the
/// file's own vertex colours where it has them. Points and lines are dropped. Coordinates stay in
/// the file's axes and units. Throws CatalogError starting with `what`.
Mesh loadAssimpMesh(const std::string& path, const FileReader& read, const std::string& what);

/// Rotation from the axes of OBJ / Sweet Home 3D / ShapeNet models (y up, front facing +z) to ours
/// (z up, front facing +x): x = z_src, y = x_src, z = y_src.
Eigen::Matrix3f worldFromYUpFrontZ();

/// Rotation from ShapeNetCore v2 axes (y up, front facing -z, as its documentation states) to ours:
/// x = -z_src, y = -x_src, z = y_src.
Eigen::Matrix3f worldFromYUpFrontMinusZ();

/// A FileReader over the local file system.
std::optional<std::string> readLocalFile(const std::string& path);

}  // namespace detail
}  // namespace occlusion_env
