// Normalised, level-of-detail meshes of a catalogue's objects, loaded once and cached.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "occlusion_env/scene/object_catalog.hpp"

namespace occlusion_env {

/// One object ready to place in a scene: centred, unit bounding-box diagonal, z up, front +x.
struct ObjectModel {
  ObjectInfo info;
  Mesh full;    // every triangle of the source
  Mesh render;  // what the renderer draws: the LOD mesh, or `full` when LOD is off
};

class ObjectLibrary {
 public:
  /// `lod_triangle_budget` = 0 renders full meshes.
  ObjectLibrary(std::shared_ptr<const ObjectCatalog> catalog, std::size_t lod_triangle_budget);

  /// Loads (first time) or returns the cached model. Thread-safe. Throws like loadMesh().
  std::shared_ptr<const ObjectModel> get(const std::string& id);

  const ObjectCatalog& catalog() const { return *catalog_; }
  std::size_t lodTriangleBudget() const { return lod_triangle_budget_; }

 private:
  std::shared_ptr<const ObjectCatalog> catalog_;
  std::size_t lod_triangle_budget_;
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const ObjectModel>> cache_;
};

}  // namespace occlusion_env
