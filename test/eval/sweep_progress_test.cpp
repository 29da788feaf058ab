// The sweep's start azimuths and scenes, and the progress bar's text.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "common/temporary_dir.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/eval/progress.hpp"
#include "occlusion_env/eval/sweep.hpp"

namespace occlusion_env {
namespace eval {
namespace {

TEST(Sweep, AzimuthsCoverHalfOpenRangeInPaperSteps) {
  const auto azimuths = sweepStartAzimuths();
  ASSERT_EQ(azimuths.size(), 13u);
  EXPECT_DOUBLE_EQ(azimuths.front(), -M_PI / 32.0);
  EXPECT_LT(azimuths.back(), M_PI / 32.0);
  for (std::size_t i = 1; i < azimuths.size(); ++i) {
    EXPECT_NEAR(azimuths[i] - azimuths[i - 1], M_PI / 208.0, 1e-12);
  }
}

TEST(Sweep, EmbeddedSweepIsOneSceneAtTheFirstSweepSeed) {
  EXPECT_EQ(defaultSweepModels("embedded"), 1);
  const SweepScenes chairs = sweepScenes("two_chairs", "embedded", 1);
  EXPECT_EQ(chairs.set.name, "sweep_two_chairs");
  EXPECT_EQ(chairs.set.preset, "two_chairs");
  EXPECT_EQ(chairs.set.seeds, std::vector<std::uint64_t>{kSweepSeed});
  ASSERT_EQ(chairs.models.size(), 1u);
  EXPECT_EQ(chairs.models[0].seed, kSweepSeed);
  EXPECT_EQ(chairs.models[0].object.category, "chair");
  EXPECT_NO_THROW(requireDisjoint(chairs.set, kTrainingSeedRange));
  EXPECT_TRUE(chairs.models[0].redrawn.empty());
  // The embedded table sweep as first published: from the outer start azimuths the start view of
  // its main table is unoccluded, so the environment redraws another table there.
  const SweepScenes tables = sweepScenes("two_tables", "embedded", 1);
  EXPECT_EQ(tables.set.seeds, std::vector<std::uint64_t>{kSweepSeed});
  ASSERT_EQ(tables.models.size(), 1u);
  EXPECT_EQ(tables.models[0].object.category, "table");
  EXPECT_FALSE(tables.models[0].redrawn.empty());
  EXPECT_LT(tables.models[0].redrawn.size(), sweepStartAzimuths().size() / 2);
  for (const auto& [azimuth, other] : tables.models[0].redrawn) {
    EXPECT_NE(other.id, tables.models[0].object.id) << "azimuth " << azimuth;
    EXPECT_EQ(other.category, "table");
  }
  // No embedded seed shows one table from every start azimuth: a sweep of several is refused.
  EXPECT_THROW(sweepScenes("two_tables", "embedded", 2), InvalidArgumentError);
  EXPECT_THROW(sweepScenes("three_lamps", "embedded", 1), InvalidArgumentError);
  EXPECT_THROW(sweepScenes("two_chairs", "embedded", 0), InvalidArgumentError);
  // The embedded catalogue holds two chairs: a third distinct model cannot be found.
  EXPECT_THROW(sweepScenes("two_chairs", "embedded", 3), InvalidArgumentError);
}

// Several Sweet Home 3D models: each seed shows one model no other seed shows, the same one (two
// copies) from every start azimuth, checked here on an environment of its own.
TEST(Sweep, SweetHome3DSweepShowsOneNewModelPerSeedAtEveryAzimuth) {
  if (defaultSweetHome3DCatalogPaths().empty()) GTEST_SKIP() << "sweethome3d-furniture missing";
  const int models = defaultSweepModels("sweethome3d");
  EXPECT_GE(models, 2);
  for (const std::string category : {"chair", "table"}) {
    SCOPED_TRACE(category);
    const std::string preset = "two_" + category + "s";
    const SweepScenes scenes = sweepScenes(preset, "sweethome3d", models);
    EXPECT_EQ(scenes.set.name, "sweep_" + preset + "_sweethome3d");
    ASSERT_EQ(scenes.models.size(), static_cast<std::size_t>(models));
    ASSERT_EQ(scenes.set.seeds.size(), scenes.models.size());
    EXPECT_NO_THROW(requireDisjoint(scenes.set, kTrainingSeedRange));
    std::set<std::string> ids;
    for (std::size_t k = 0; k < scenes.models.size(); ++k) {
      const SweepModel& model = scenes.models[k];
      EXPECT_EQ(model.seed, scenes.set.seeds[k]);
      EXPECT_GE(model.seed, kSweepSeed);
      if (k > 0) {
        EXPECT_GT(model.seed, scenes.models[k - 1].seed);
      }
      EXPECT_EQ(model.object.category, category);
      EXPECT_TRUE(model.split == "train" || model.split == "test") << model.split;
      EXPECT_TRUE(model.redrawn.empty());
      EXPECT_TRUE(ids.insert(model.object.id).second) << "model drawn twice: " << model.object.id;
    }
    for (const SkippedSweepSeed& skipped : scenes.skipped) {
      EXPECT_GE(skipped.seed, kSweepSeed);
      EXPECT_LT(skipped.seed, scenes.set.seeds.back());
      EXPECT_EQ(std::count(scenes.set.seeds.begin(), scenes.set.seeds.end(), skipped.seed), 0);
      EXPECT_FALSE(skipped.reason.empty());
    }
    // Seeds are taken in order: every seed up to the last is either in the set or skipped.
    EXPECT_EQ(scenes.set.seeds.size() + scenes.skipped.size(),
              scenes.set.seeds.back() - kSweepSeed + 1);
    Environment environment(environmentOptionsFor(scenes.set));
    ResetOptions reset = resetOptionsFor(scenes.set);
    for (const SweepModel& model : scenes.models) {
      for (const double azimuth : sweepStartAzimuths()) {
        reset.start_azimuth_rad = azimuth;
        environment.reset(model.seed, reset);
        const Scene& scene = environment.scene();
        ASSERT_EQ(scene.objects.size(), 2u);
        EXPECT_EQ(scene.objects[0].model->info.id, model.object.id) << "azimuth " << azimuth;
        EXPECT_EQ(scene.objects[1].model->info.id, model.object.id) << "azimuth " << azimuth;
      }
    }
  }
}

// The models' CSV written and read in a scratch folder of its own.
class SweepCsvTest : public TemporaryDirTest {};

TEST_F(SweepCsvTest, ModelsCsvQuotesTextFields) {
  SweepModel model;
  model.seed = 1'002'003;
  model.object.id = "cat/id";
  model.object.name = "Chair, \"Oak\"";
  model.object.category = "chair";
  model.object.license = "CC0";
  model.object.dimensions_m = Eigen::Vector3f(0.5f, 0.25f, 1.0f);
  model.split = "test";
  ObjectInfo other;
  other.id = "other";
  other.category = "chair";
  model.redrawn = {{-M_PI / 32.0, other}};
  const auto path = (dir_ / "sweep_models.csv").string();
  writeSweepModelsCsv({model}, path);
  std::ifstream in(path);
  std::string header, row, rest;
  std::getline(in, header);
  std::getline(in, row);
  EXPECT_EQ(header, "seed,id,name,category,split,creator,license,width_m,depth_m,height_m,redrawn");
  EXPECT_EQ(row, R"(1002003,"cat/id","Chair, ""Oak""","chair",test,"","CC0",0.5,0.25,1,)"
                 R"("-5.62 deg: other")");
  EXPECT_FALSE(std::getline(in, rest));
  EXPECT_THROW(writeSweepModelsCsv({model}, "/nonexistent_dir/models.csv"), InvalidArgumentError);
}

TEST(Progress, ShowsFractionAndEta) {
  std::ostringstream out;
  ProgressBar bar(out, 40, "eval");
  // 10 of 40 done in 30 s: 90 s to go at that rate.
  const std::string line = bar.render(10, 30.0, "random");
  EXPECT_NE(line.find(" 25% 10/40"), std::string::npos) << line;
  EXPECT_NE(line.find("elapsed 30s ETA 1m30s"), std::string::npos) << line;
  EXPECT_NE(line.find("random"), std::string::npos);
  // A run resumed at 30 of 40 that did 5 more in 10 s: 10 s to go, not the 1 s that counting
  // the resumed work would say.
  bar.resumeFrom(30);
  const std::string resumed = bar.render(35, 10.0, "");
  EXPECT_NE(resumed.find(" 87% 35/40 elapsed 10s ETA 10s"), std::string::npos) << resumed;
  EXPECT_EQ(formatDuration(3725.0), "1h02m");
  EXPECT_EQ(formatDuration(-1.0), "?");
}

}  // namespace
}  // namespace eval
}  // namespace occlusion_env
