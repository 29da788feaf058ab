// Scene sets: the shipped test sets load, are disjoint from training and from each other, and
// the disjointness checks catch overlaps.
#include "occlusion_env/env/scene_set.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "common/temporary_dir.hpp"
#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

// Scene-set files written and read in a scratch folder of their own.
class SceneSetFileTest : public TemporaryDirTest {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    const auto path = dir_ / name;
    std::ofstream(path) << text;
    return path.string();
  }
};

// Evaluations refuse the seeds trainers draw from, and take the validation set's.
TEST(SceneSet, TheValidationSetIsAboveEveryTrainersSeeds) {
  const SceneSet validation = loadSceneSet("config/scenes/validation_sweethome3d.yaml");
  EXPECT_EQ(validation.seeds.size(), 50u);
  EXPECT_EQ(validation.model_split, "train");
  EXPECT_NO_THROW(requireDisjoint(validation, kTrainerSeedRange));
  EXPECT_THROW(requireDisjoint(validation, kTrainingSeedRange), InvalidArgumentError);
  EXPECT_NO_THROW(requireDisjoint(validation, loadSceneSet("config/scenes/test_sweethome3d.yaml")));
  SceneSet drawn = validation;
  drawn.seeds = {kFirstValidationSeed - 1};
  EXPECT_THROW(requireDisjoint(drawn, kTrainerSeedRange), InvalidArgumentError);
  // The larger set (scripts/dagger.sh's choice) begins with the same 50 scenes.
  const SceneSet larger = loadSceneSet("config/scenes/validation_sweethome3d_200.yaml");
  ASSERT_EQ(larger.seeds.size(), 200u);
  EXPECT_TRUE(std::equal(validation.seeds.begin(), validation.seeds.end(), larger.seeds.begin()));
  EXPECT_EQ(larger.model_split, "train");
  EXPECT_NO_THROW(requireDisjoint(larger, kTrainerSeedRange));
  EXPECT_NO_THROW(requireDisjoint(larger, loadSceneSet("config/scenes/test_sweethome3d.yaml")));
}

TEST(SceneSet, ShippedTestSetsAreFiftyTestSeedsAtAzimuthZero) {
  for (const char* file :
       {"config/scenes/test_embedded.yaml", "config/scenes/test_sweethome3d.yaml"}) {
    SCOPED_TRACE(file);
    const SceneSet set = loadSceneSet(file);
    EXPECT_EQ(set.seeds.size(), 50u);
    EXPECT_EQ(set.num_objects, 3);
    EXPECT_EQ(set.start_azimuth_rad, 0.0);
    EXPECT_EQ(set.start_elevation_rad, 0.0);
    EXPECT_EQ(set.preset, "random");
    EXPECT_NO_THROW(requireDisjoint(set, kTrainingSeedRange));
  }
  const SceneSet embedded = loadSceneSet("config/scenes/test_embedded.yaml");
  const SceneSet furniture = loadSceneSet("config/scenes/test_sweethome3d.yaml");
  EXPECT_EQ(embedded.source, "embedded");
  EXPECT_EQ(furniture.source, "sweethome3d");
  EXPECT_EQ(embedded.seeds.front(), 1'000'000u);
  EXPECT_EQ(embedded.seeds.back(), 1'000'049u);
  EXPECT_NO_THROW(requireDisjoint(embedded, furniture));
}

TEST(SceneSet, DisjointnessChecksFindSharedSeeds) {
  SceneSet a;
  a.name = "a";
  a.seeds = {5, 1'000'003, 9};
  SceneSet b;
  b.name = "b";
  b.seeds = {1'000'003, 9, 12};
  EXPECT_EQ(sharedSeeds(a, b), (std::vector<std::uint64_t>{9, 1'000'003}));
  EXPECT_THROW(requireDisjoint(a, b), InvalidArgumentError);
  EXPECT_EQ(seedsInRange(a, kTrainingSeedRange), (std::vector<std::uint64_t>{5, 9}));
  EXPECT_THROW(requireDisjoint(a, kTrainingSeedRange), InvalidArgumentError);
  SceneSet c;
  c.name = "c";
  c.seeds = {1'000'010, 1'000'011};
  EXPECT_NO_THROW(requireDisjoint(a, c));
  EXPECT_NO_THROW(requireDisjoint(c, kTrainingSeedRange));
  EXPECT_FALSE((SeedRange{10, 5}).contains(15));
  EXPECT_TRUE((SeedRange{10, 5}).contains(14));
}

TEST_F(SceneSetFileTest, SaveThenLoadRoundTripsAndSeedRangeExpands) {
  SceneSet set;
  set.name = "round_trip";
  set.description = "a: test";
  set.source = "sweethome3d";
  set.categories = {"chair", "table"};
  set.preset = "two_chairs";
  set.num_objects = 2;
  set.start_azimuth_rad = -0.0625;
  set.seeds = {1'000'020, 1'000'007};
  const auto path = (dir_ / "scene_set_round_trip.yaml").string();
  saveSceneSet(set, path);
  const SceneSet loaded = loadSceneSet(path);
  EXPECT_EQ(loaded.name, set.name);
  EXPECT_EQ(loaded.description, set.description);
  EXPECT_EQ(loaded.source, set.source);
  EXPECT_EQ(loaded.categories, set.categories);
  EXPECT_EQ(loaded.preset, set.preset);
  EXPECT_EQ(loaded.num_objects, 2);
  EXPECT_EQ(loaded.start_azimuth_rad, -0.0625);
  EXPECT_EQ(loaded.seeds, set.seeds);

  const auto range_path =
      write("scene_set_range.yaml", "name: r\nseed_range: {first: 1000000, count: 3}\n");
  EXPECT_EQ(loadSceneSet(range_path).seeds,
            (std::vector<std::uint64_t>{1'000'000, 1'000'001, 1'000'002}));
}

TEST_F(SceneSetFileTest, BadFilesAreRejectedNamingTheKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"seeds: [1, 2]\nsede: 3\n", "sede"},
      {"seeds: [1, 2, 1]\n", "duplicate"},
      {"name: x\n", "seeds"},
      {"seeds: [1]\npreset: three_lamps\n", "preset"},
      {"seeds: [1]\nseed_range: {first: 1, count: 2}\n", "not both"},
      {"seeds: [a]\n", "seeds"},
  };
  for (const auto& [text, expected] : cases) {
    const auto path = write("scene_set_bad.yaml", text);
    try {
      loadSceneSet(path);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InvalidArgumentError& error) {
      EXPECT_NE(std::string(error.what()).find(expected), std::string::npos) << error.what();
    }
  }
  EXPECT_THROW(loadSceneSet("/nonexistent/scenes.yaml"), InvalidArgumentError);
}

TEST(SceneSet, OptionsCarryTheSetsChoices) {
  const SceneSet set = loadSceneSet("config/scenes/test_sweethome3d.yaml");
  const EnvironmentOptions options = environmentOptionsFor(set);
  EXPECT_EQ(options.catalog.source, "sweethome3d");
  EXPECT_EQ(options.scene.categories, set.categories);
  EXPECT_EQ(options.scene.num_objects, 3);
  const ResetOptions reset = resetOptionsFor(set);
  ASSERT_TRUE(reset.start_azimuth_rad.has_value());
  EXPECT_EQ(*reset.start_azimuth_rad, 0.0);
  EXPECT_EQ(*reset.start_elevation_rad, 0.0);
  EXPECT_EQ(*reset.preset, "random");
}

}  // namespace

}  // namespace occlusion_env
