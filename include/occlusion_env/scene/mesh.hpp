// Triangle meshes as the core stores them: object coordinates in metres, z up (REP 103).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace occlusion_env {

/// An indexed triangle mesh with one colour per vertex (linear RGB in [0, 1]).
/// Textures are baked into the vertex colours when a mesh is loaded.
struct Mesh {
  std::vector<Eigen::Vector3f> positions;  // [m]
  std::vector<Eigen::Vector3f> colors;     // RGB in [0, 1], one per position
  std::vector<std::uint32_t> indices;      // three per triangle

  std::size_t vertexCount() const { return positions.size(); }
  std::size_t triangleCount() const { return indices.size() / 3; }
  bool empty() const { return indices.empty(); }
};

/// Axis-aligned bounding box of the referenced vertices. Throws InvalidArgumentError if empty.
Eigen::AlignedBox3f boundingBox(const Mesh& mesh);

/// Throws CatalogError (message starting with `what`) unless the mesh is non-empty, has one colour
/// per vertex, in-range indices and only finite coordinates.
void validateMesh(const Mesh& mesh, const std::string& what);

/// Centres the bounding box at the origin and scales it to a unit diagonal (ShapeNet's convention).
void normalizeToUnitDiagonal(Mesh& mesh);

/// Appends `part` to `mesh`, transformed by `transform`.
void appendMesh(Mesh& mesh, const Mesh& part,
                const Eigen::Affine3f& transform = Eigen::Affine3f::Identity());

/// Level-of-detail copy with at most `max_triangles` triangles (meshoptimizer). Vertices shared by
/// position are welded first, so seams in UV or normals do not block simplification. Returns a
/// copy of the input when it is already within budget. Unreferenced vertices are dropped.
Mesh simplifyMesh(const Mesh& mesh, std::size_t max_triangles);

}  // namespace occlusion_env
