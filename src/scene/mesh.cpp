#include "occlusion_env/scene/mesh.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <unordered_map>
#include <unordered_set>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

Eigen::AlignedBox3f boundingBox(const Mesh& mesh) {
  if (mesh.indices.empty()) throw InvalidArgumentError("boundingBox: empty mesh");
  Eigen::AlignedBox3f box;
  for (std::uint32_t index : mesh.indices) box.extend(mesh.positions[index]);
  return box;
}

void validateMesh(const Mesh& mesh, const std::string& what) {
  if (mesh.indices.empty() || mesh.positions.empty())
    throw CatalogError(what + ": mesh has no triangles");
  if (mesh.indices.size() % 3 != 0)
    throw CatalogError(what + ": index count is not a multiple of 3");
  if (mesh.colors.size() != mesh.positions.size())
    throw CatalogError(what + ": colour count differs from vertex count");
  for (std::uint32_t index : mesh.indices)
    if (index >= mesh.positions.size()) throw CatalogError(what + ": vertex index out of range");
  for (const auto& p : mesh.positions)
    if (!p.allFinite()) throw CatalogError(what + ": non-finite vertex coordinate");
  const Eigen::AlignedBox3f box = boundingBox(mesh);
  if (!(box.diagonal().norm() > 0.0f)) throw CatalogError(what + ": mesh has zero extent");
}

void normalizeToUnitDiagonal(Mesh& mesh) {
  const Eigen::AlignedBox3f box = boundingBox(mesh);
  const float diagonal = box.diagonal().norm();
  if (!(diagonal > 0.0f)) throw InvalidArgumentError("normalizeToUnitDiagonal: zero extent");
  const Eigen::Vector3f centre = box.center();
  for (auto& p : mesh.positions) p = (p - centre) / diagonal;
}

void appendMesh(Mesh& mesh, const Mesh& part, const Eigen::Affine3f& transform) {
  const auto offset = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.reserve(mesh.positions.size() + part.positions.size());
  for (const auto& p : part.positions) mesh.positions.push_back(transform * p);
  mesh.colors.insert(mesh.colors.end(), part.colors.begin(), part.colors.end());
  mesh.indices.reserve(mesh.indices.size() + part.indices.size());
  for (std::uint32_t index : part.indices) mesh.indices.push_back(index + offset);
}

namespace {

// Indices into a copy of `mesh` whose vertices are unique by position, so that simplification can
// collapse across seams in colour or texture coordinates.
struct TriangleHash {
  std::size_t operator()(const std::array<std::uint32_t, 3>& t) const {
    return (static_cast<std::size_t>(t[0]) * 73856093u) ^
           (static_cast<std::size_t>(t[1]) * 19349663u) ^
           (static_cast<std::size_t>(t[2]) * 83492791u);
  }
};

Mesh weldByPosition(const Mesh& mesh) {
  struct KeyHash {
    std::size_t operator()(const Eigen::Vector3f& p) const {
      std::size_t h = 1469598103934665603ull;
      for (int i = 0; i < 3; ++i) {
        std::uint32_t bits;
        std::memcpy(&bits, &p[i], sizeof bits);
        h = (h ^ bits) * 1099511628211ull;
      }
      return h;
    }
  };
  Mesh welded;
  std::unordered_map<Eigen::Vector3f, std::uint32_t, KeyHash> first_of;
  first_of.reserve(mesh.positions.size());
  std::vector<std::uint32_t> remap(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    auto [it, inserted] =
        first_of.emplace(mesh.positions[v], static_cast<std::uint32_t>(welded.positions.size()));
    if (inserted) {
      welded.positions.push_back(mesh.positions[v]);
      welded.colors.push_back(mesh.colors[v]);
    }
    remap[v] = it->second;
  }
  welded.indices.reserve(mesh.indices.size());
  // Double-sided surfaces are often modelled as two copies with opposite winding; after welding
  // they share every edge, which the simplifier treats as removable. Nothing is culled, so one
  // copy of each triangle (as a vertex set) is enough.
  std::unordered_set<std::array<std::uint32_t, 3>, TriangleHash> seen;
  seen.reserve(mesh.indices.size() / 3);
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::uint32_t a = remap[mesh.indices[t]], b = remap[mesh.indices[t + 1]],
                        c = remap[mesh.indices[t + 2]];
    if (a == b || b == c || a == c) continue;  // degenerate after welding
    std::array<std::uint32_t, 3> key{a, b, c};
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) continue;  // the same triangle again (e.g. its back face)
    welded.indices.insert(welded.indices.end(), {a, b, c});
  }
  return welded;
}

// Drops vertices no triangle references and renumbers the indices.
Mesh compact(const Mesh& mesh, const std::vector<std::uint32_t>& indices) {
  Mesh out;
  std::vector<std::uint32_t> new_index(mesh.positions.size(), UINT32_MAX);
  out.indices.reserve(indices.size());
  for (std::uint32_t index : indices) {
    if (new_index[index] == UINT32_MAX) {
      new_index[index] = static_cast<std::uint32_t>(out.positions.size());
      out.positions.push_back(mesh.positions[index]);
      out.colors.push_back(mesh.colors[index]);
    }
    out.indices.push_back(new_index[index]);
  }
  return out;
}

}  // namespace

Mesh simplifyMesh(const Mesh& mesh, std::size_t max_triangles) {
  if (max_triangles == 0) throw InvalidArgumentError("simplifyMesh: max_triangles must be > 0");
  if (mesh.triangleCount() <= max_triangles) return compact(mesh, mesh.indices);

  const Mesh welded = weldByPosition(mesh);
  if (welded.triangleCount() <= max_triangles) return compact(welded, welded.indices);

  const std::size_t target_index_count = max_triangles * 3;
  std::vector<std::uint32_t> indices(welded.indices.size());
  // Attribute-free, topology-preserving simplification; no error limit (the budget decides).
  std::size_t count = meshopt_simplify(
      indices.data(), welded.indices.data(), welded.indices.size(), welded.positions[0].data(),
      welded.positions.size(), sizeof(Eigen::Vector3f), target_index_count, 1.0f, 0, nullptr);
  indices.resize(count);
  if (count > target_index_count) {
    // Topology (e.g. many separate parts) blocked the collapse: finish with clustering.
    std::vector<std::uint32_t> sloppy(indices.size());
    count = meshopt_simplifySloppy(sloppy.data(), indices.data(), indices.size(),
                                   welded.positions[0].data(), welded.positions.size(),
                                   sizeof(Eigen::Vector3f), target_index_count, 1.0f, nullptr);
    sloppy.resize(count);
    indices.swap(sloppy);
  }
  if (indices.empty()) return compact(welded, welded.indices);  // never return an empty mesh
  // Triangle order for the post-transform vertex cache; compact() then orders vertices by first
  // use, which is what vertex fetch wants.
  std::vector<std::uint32_t> ordered(indices.size());
  meshopt_optimizeVertexCache(ordered.data(), indices.data(), indices.size(),
                              welded.positions.size());
  return compact(welded, ordered);
}

}  // namespace occlusion_env
