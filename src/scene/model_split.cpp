#include "occlusion_env/scene/model_split.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

constexpr double kTestFraction = 0.2;

std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t hash = 14695981039346656037ull;
  for (const unsigned char c : text) hash = (hash ^ c) * 1099511628211ull;
  return hash;
}

}  // namespace

ModelSplit parseModelSplit(const std::string& text) {
  if (text == "all") return ModelSplit::kAll;
  if (text == "train") return ModelSplit::kTrain;
  if (text == "test") return ModelSplit::kTest;
  throw InvalidArgumentError("model split must be all, train or test, got " + quoted(text));
}

std::string toString(ModelSplit split) {
  switch (split) {
    case ModelSplit::kAll:
      return "all";
    case ModelSplit::kTrain:
      return "train";
    case ModelSplit::kTest:
      return "test";
  }
  return "unknown";
}

ModelSplit modelSplitOf(const ObjectCatalog& catalog, const std::string& id) {
  const ObjectInfo* info = catalog.find(id);
  if (info == nullptr) {
    throw InvalidArgumentError("unknown object id " + quoted(id) + " in the " +
                               catalog.sourceName() + " catalogue");
  }
  std::vector<std::string> ids = catalog.idsInCategory(info->category);
  if (ids.size() < 2) return ModelSplit::kTrain;
  std::sort(ids.begin(), ids.end(), [](const std::string& a, const std::string& b) {
    const std::uint64_t ha = fnv1a(a), hb = fnv1a(b);
    return ha != hb ? ha < hb : a < b;
  });
  const std::size_t test_count = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::lround(kTestFraction * static_cast<double>(ids.size()))));
  const auto position = std::find(ids.begin(), ids.end(), id) - ids.begin();
  return static_cast<std::size_t>(position) < test_count ? ModelSplit::kTest : ModelSplit::kTrain;
}

std::vector<std::string> idsInSplit(const ObjectCatalog& catalog,
                                    const std::vector<std::string>& ids, ModelSplit split) {
  if (split == ModelSplit::kAll) return ids;
  std::vector<std::string> kept;
  for (const std::string& id : ids) {
    if (modelSplitOf(catalog, id) == split) kept.push_back(id);
  }
  return kept;
}

}  // namespace occlusion_env
