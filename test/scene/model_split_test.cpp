#include "occlusion_env/scene/model_split.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/scene/object_catalog.hpp"

namespace occlusion_env {
namespace {

// Every category splits into train and test, about a fifth of it test (one at least, none of a
// single model), and each id's own split is the one the lists give it.
void expectPartitions(const ObjectCatalog& catalog) {
  for (const std::string& category : catalog.categories()) {
    SCOPED_TRACE(catalog.sourceName() + " " + category);
    const std::vector<std::string> ids = catalog.idsInCategory(category);
    const std::vector<std::string> train = idsInSplit(catalog, ids, ModelSplit::kTrain);
    const std::vector<std::string> test = idsInSplit(catalog, ids, ModelSplit::kTest);
    const std::size_t expected_test =
        ids.size() < 2 ? 0 : std::max<std::size_t>(1, std::lround(0.2 * ids.size()));
    EXPECT_EQ(test.size(), expected_test);
    EXPECT_EQ(train.size() + test.size(), ids.size());
    std::set<std::string> both(train.begin(), train.end());
    both.insert(test.begin(), test.end());
    EXPECT_EQ(both, std::set<std::string>(ids.begin(), ids.end()));
    for (const std::string& id : train) EXPECT_EQ(modelSplitOf(catalog, id), ModelSplit::kTrain);
    for (const std::string& id : test) EXPECT_EQ(modelSplitOf(catalog, id), ModelSplit::kTest);
    EXPECT_EQ(idsInSplit(catalog, ids, ModelSplit::kAll), ids);
  }
}

TEST(ModelSplit, TheEmbeddedObjectsSplitAsTheyAlwaysHave) {
  // Datasets, shipped models and held-out sets rest on which models are test models: a change
  // here would put test models into training.
  const std::unique_ptr<ObjectCatalog> catalog = makeEmbeddedCatalog();
  std::vector<std::string> all;
  for (const ObjectInfo& object : catalog->objects()) all.push_back(object.id);
  const std::vector<std::string> test = idsInSplit(*catalog, all, ModelSplit::kTest);
  EXPECT_EQ(std::set<std::string>(test.begin(), test.end()),
            (std::set<std::string>{"embedded/chair_slat", "embedded/lamp_floor",
                                   "embedded/table_round"}));
  expectPartitions(*catalog);
}

TEST(ModelSplit, IdsOfSeveralCategoriesKeepTheirOrder) {
  const std::unique_ptr<ObjectCatalog> catalog = makeEmbeddedCatalog();
  const std::vector<std::string> mixed = {"embedded/table_round", "embedded/chair_office",
                                          "embedded/chair_slat", "embedded/mug",
                                          "embedded/table_dining"};
  EXPECT_EQ(
      idsInSplit(*catalog, mixed, ModelSplit::kTrain),
      (std::vector<std::string>{"embedded/chair_office", "embedded/mug", "embedded/table_dining"}));
  EXPECT_EQ(idsInSplit(*catalog, mixed, ModelSplit::kTest),
            (std::vector<std::string>{"embedded/table_round", "embedded/chair_slat"}));
  EXPECT_THROW(modelSplitOf(*catalog, "embedded/no_such_thing"), InvalidArgumentError);
  EXPECT_THROW(idsInSplit(*catalog, {"embedded/no_such_thing"}, ModelSplit::kTrain),
               InvalidArgumentError);
}

TEST(ModelSplit, SweetHome3DCategoriesArePartitioned) {
  if (!std::filesystem::is_directory("/usr/share/sweethome3d/furniture")) {
    GTEST_SKIP() << "sweethome3d-furniture is not installed";
  }
  expectPartitions(*makeCatalog({"sweethome3d", {}}));
}

}  // namespace
}  // namespace occlusion_env
