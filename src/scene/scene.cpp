#include "occlusion_env/scene/scene.hpp"

#include <sstream>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/limits.hpp"

namespace occlusion_env {
namespace {

std::string joined(const std::vector<std::string>& words) {
  std::ostringstream out;
  for (std::size_t i = 0; i < words.size(); ++i) out << (i ? ", " : "") << words[i];
  return out.str();
}

/// The ids a random draw may pick from: every object of the given categories, or every object,
/// of the split.
std::vector<std::string> candidateIds(const ObjectCatalog& catalog,
                                      const std::vector<std::string>& categories,
                                      ModelSplit split) {
  std::vector<std::string> ids;
  if (categories.empty()) {
    for (const ObjectInfo& info : catalog.objects()) ids.push_back(info.id);
  }
  for (const std::string& category : categories) {
    const std::vector<std::string> in_category = catalog.idsInCategory(category);
    if (in_category.empty()) {
      throw InvalidArgumentError("no object of category " + quoted(category) + " in the " +
                                 catalog.sourceName() +
                                 " catalogue; categories: " + joined(catalog.categories()));
    }
    ids.insert(ids.end(), in_category.begin(), in_category.end());
  }
  if (ids.empty()) {
    throw InvalidArgumentError("the " + catalog.sourceName() + " catalogue holds no objects");
  }
  ids = idsInSplit(catalog, ids, split);
  if (ids.empty()) {
    throw InvalidArgumentError("no object of the " + toString(split) + " split among " +
                               (categories.empty() ? "the catalogue's" : joined(categories)));
  }
  return ids;
}

// Explicit ids must lie in the split (a training run must not see a test model).
void requireInSplit(const ObjectCatalog& catalog, const std::vector<std::string>& ids,
                    ModelSplit split) {
  if (split == ModelSplit::kAll) return;
  for (const std::string& id : ids) {
    if (catalog.find(id) && modelSplitOf(catalog, id) != split) {
      throw InvalidArgumentError("object " + quoted(id) + " is not in the " + toString(split) +
                                 " split of the " + catalog.sourceName() + " catalogue");
    }
  }
}

std::shared_ptr<const ObjectModel> modelOf(ObjectLibrary& library, const std::string& id) {
  if (!library.catalog().find(id)) {
    throw InvalidArgumentError("unknown object id " + quoted(id) + " in the " +
                               library.catalog().sourceName() +
                               " catalogue (occlusion_render --list prints the ids)");
  }
  return library.get(id);
}

}  // namespace

ScenePreset parseScenePreset(const std::string& text) {
  if (text == "random") return ScenePreset::kRandom;
  if (text == "two_chairs") return ScenePreset::kTwoChairs;
  if (text == "two_tables") return ScenePreset::kTwoTables;
  throw InvalidArgumentError("scene preset must be random, two_chairs or two_tables, got " +
                             quoted(text));
}

std::string toString(ScenePreset preset) {
  switch (preset) {
    case ScenePreset::kRandom:
      return "random";
    case ScenePreset::kTwoChairs:
      return "two_chairs";
    case ScenePreset::kTwoTables:
      return "two_tables";
  }
  return "unknown";
}

Scene generateScene(ObjectLibrary& library, const SceneOptions& options, ScenePreset preset,
                    RandomSource& random) {
  const ObjectCatalog& catalog = library.catalog();
  Scene scene;

  if (preset != ScenePreset::kRandom) {
    // Two copies of one model, the second 2 spacings nearer the camera, no sideways offset.
    std::string id;
    if (!options.object_ids.empty()) {
      id = options.object_ids.front();
      requireInSplit(catalog, {id}, options.model_split);
    } else {
      const std::vector<std::string> ids = candidateIds(
          catalog, {preset == ScenePreset::kTwoChairs ? "chair" : "table"}, options.model_split);
      id = ids[random.below(ids.size())];
    }
    const auto model = modelOf(library, id);
    scene.objects.push_back({model, Eigen::Vector3d::Zero()});
    scene.objects.push_back({model, Eigen::Vector3d(2.0 * options.depth_spacing_m, 0.0, 0.0)});
    return scene;
  }

  std::vector<std::string> ids = options.object_ids;
  if (ids.empty()) {
    if (options.num_objects < 1 || options.num_objects > kMaxSceneObjects) {
      throw InvalidArgumentError("num_objects must lie in [1, " + std::to_string(kMaxSceneObjects) +
                                 "], got " + std::to_string(options.num_objects));
    }
    const std::vector<std::string> candidates =
        candidateIds(catalog, options.categories, options.model_split);
    for (int k = 0; k < options.num_objects; ++k) {
      ids.push_back(candidates[random.below(candidates.size())]);
    }
  } else if (ids.size() > static_cast<std::size_t>(kMaxSceneObjects)) {
    throw InvalidArgumentError("a scene holds at most " + std::to_string(kMaxSceneObjects) +
                               " objects, got " + std::to_string(ids.size()) + " ids");
  } else {
    requireInSplit(catalog, ids, options.model_split);
  }

  // One sideways offset per scene; odd objects go to +x, even ones to -x (paper, Section 3).
  const double sideways_m = random.normal(0.0, options.lateral_sigma_m);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    if (k > 0) {
      position.x() = static_cast<double>(k) * options.depth_spacing_m;
      position.y() = (k % 2 == 1) ? sideways_m : -sideways_m;
    }
    scene.objects.push_back({modelOf(library, ids[k]), position});
  }
  return scene;
}

}  // namespace occlusion_env
