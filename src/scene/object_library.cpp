#include "occlusion_env/scene/object_library.hpp"

#include <utility>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

ObjectLibrary::ObjectLibrary(std::shared_ptr<const ObjectCatalog> catalog,
                             std::size_t lod_triangle_budget)
    : catalog_(std::move(catalog)), lod_triangle_budget_(lod_triangle_budget) {
  if (!catalog_) throw InvalidArgumentError("ObjectLibrary: catalog must not be null");
}

std::shared_ptr<const ObjectModel> ObjectLibrary::get(const std::string& id) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = cache_.find(id);
    if (it != cache_.end()) return it->second;
  }
  const ObjectInfo* info = catalog_->find(id);
  if (info == nullptr)
    throw InvalidArgumentError("unknown object id " + quoted(id) + " in the " +
                               catalog_->sourceName() +
                               " catalogue; list the valid ids with ObjectCatalog::objects()");

  // Loaded without the lock so that other objects load in parallel; two threads asking for the
  // same new id may both load it, and the first to finish wins.
  auto model = std::make_shared<ObjectModel>();
  model->info = *info;
  model->full = catalog_->loadMesh(id);
  normalizeToUnitDiagonal(model->full);
  model->render =
      lod_triangle_budget_ > 0 ? simplifyMesh(model->full, lod_triangle_budget_) : model->full;

  std::lock_guard<std::mutex> lock(mutex_);
  return cache_.emplace(id, std::move(model)).first->second;
}

}  // namespace occlusion_env
