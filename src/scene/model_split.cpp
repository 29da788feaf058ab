#include "occlusion_env/scene/model_split.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

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

namespace {

// The test models of `category`: the first 20 % (at least one; none of a single model) of its ids
// ordered by hash, then by id; sorted by id.
std::vector<std::string> testIdsOf(const ObjectCatalog& catalog, const std::string& category) {
  const std::vector<std::string> ids = catalog.idsInCategory(category);
  if (ids.size() < 2) return {};
  std::vector<std::pair<std::uint64_t, const std::string*>> keyed;
  keyed.reserve(ids.size());
  for (const std::string& id : ids) keyed.emplace_back(fnv1a(id), &id);
  std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : *a.second < *b.second;
  });
  const std::size_t test_count = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::lround(kTestFraction * static_cast<double>(ids.size()))));
  std::vector<std::string> test;
  for (std::size_t k = 0; k < test_count; ++k) test.push_back(*keyed[k].second);
  std::sort(test.begin(), test.end());
  return test;
}

const ObjectInfo& infoOf(const ObjectCatalog& catalog, const std::string& id) {
  const ObjectInfo* info = catalog.find(id);
  if (info == nullptr) {
    throw InvalidArgumentError("unknown object id " + quoted(id) + " in the " +
                               catalog.sourceName() + " catalogue");
  }
  return *info;
}

}  // namespace

ModelSplit modelSplitOf(const ObjectCatalog& catalog, const std::string& id) {
  const std::vector<std::string> test = testIdsOf(catalog, infoOf(catalog, id).category);
  return std::binary_search(test.begin(), test.end(), id) ? ModelSplit::kTest : ModelSplit::kTrain;
}

std::vector<std::string> idsInSplit(const ObjectCatalog& catalog,
                                    const std::vector<std::string>& ids, ModelSplit split) {
  if (split == ModelSplit::kAll) return ids;
  // Each category's test models once, not once per id.
  std::map<std::string, std::vector<std::string>> test_ids_by_category;
  std::vector<std::string> kept;
  for (const std::string& id : ids) {
    const std::string& category = infoOf(catalog, id).category;
    auto found = test_ids_by_category.find(category);
    if (found == test_ids_by_category.end()) {
      found = test_ids_by_category.emplace(category, testIdsOf(catalog, category)).first;
    }
    const std::vector<std::string>& test = found->second;
    const bool in_test = std::binary_search(test.begin(), test.end(), id);
    if (in_test == (split == ModelSplit::kTest)) kept.push_back(id);
  }
  return kept;
}

}  // namespace occlusion_env
