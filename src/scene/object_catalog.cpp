#include "occlusion_env/scene/object_catalog.hpp"

#include <algorithm>
#include <set>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

const ObjectInfo* ObjectCatalog::find(const std::string& id) const {
  const auto& all = objects();
  const auto it = std::lower_bound(
      all.begin(), all.end(), id,
      [](const ObjectInfo& object, const std::string& key) { return object.id < key; });
  if (it != all.end() && it->id == id) return &*it;
  // Not sorted after all (a catalogue breaking the contract): fall back to a linear search.
  const auto linear = std::find_if(all.begin(), all.end(),
                                   [&](const ObjectInfo& object) { return object.id == id; });
  return linear == all.end() ? nullptr : &*linear;
}

std::vector<std::string> ObjectCatalog::idsInCategory(const std::string& category) const {
  std::vector<std::string> ids;
  for (const auto& object : objects())
    if (object.category == category) ids.push_back(object.id);
  std::sort(ids.begin(), ids.end());
  return ids;
}

std::vector<std::string> ObjectCatalog::categories() const {
  std::set<std::string> distinct;
  for (const auto& object : objects()) distinct.insert(object.category);
  return {distinct.begin(), distinct.end()};
}

std::unique_ptr<ObjectCatalog> makeCatalog(const CatalogOptions& options) {
  if (options.source == "embedded") return makeEmbeddedCatalog();  // paths are not used
  if (options.source == "sweethome3d") {
    std::vector<std::string> paths = options.paths;
    if (paths.empty()) paths = defaultSweetHome3DCatalogPaths();
    if (paths.empty())
      throw CatalogError(
          "catalog source 'sweethome3d': no .sh3f catalogue installed in "
          "/usr/share/sweethome3d/furniture; install it with `apt install sweethome3d-furniture` "
          "or list .sh3f files in the catalog paths");
    return makeSweetHome3DCatalog(paths);
  }
  if (options.source == "folder") {
    if (options.paths.size() != 1)
      throw InvalidArgumentError(
          "catalog source 'folder' needs exactly one path (the root folder), got " +
          std::to_string(options.paths.size()));
    return makeMeshFolderCatalog(options.paths.front());
  }
  throw InvalidArgumentError("unknown catalog source '" + options.source +
                             "'; valid sources: embedded, sweethome3d, folder");
}

}  // namespace occlusion_env
