#include "occlusion_env/scene/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

/// A catalogue of unit boxes in two categories, so that scene tests need no mesh data.
class BoxCatalog : public ObjectCatalog {
 public:
  BoxCatalog() {
    for (const char* id : {"box/a", "box/b", "box/c"}) {
      ObjectInfo info;
      info.id = id;
      info.name = id;
      info.category = "chair";
      objects_.push_back(info);
    }
    ObjectInfo table;
    table.id = "box/t";
    table.name = "table";
    table.category = "table";
    objects_.push_back(table);
  }
  std::string sourceName() const override { return "boxes"; }
  const std::vector<ObjectInfo>& objects() const override { return objects_; }
  Mesh loadMesh(const std::string& id) const override {
    if (!find(id)) throw InvalidArgumentError("unknown id " + id);
    Mesh mesh;
    for (int corner = 0; corner < 8; ++corner) {
      mesh.positions.emplace_back(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
      mesh.colors.emplace_back(1.0f, 1.0f, 1.0f);
    }
    mesh.indices = {0, 1, 2, 1, 3, 2, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4};
    return mesh;
  }

 private:
  std::vector<ObjectInfo> objects_;
};

TEST(SceneTest, PlacesObjectsAsThePaper) {
  ObjectLibrary library(std::make_shared<BoxCatalog>(), 0);
  RandomSource random(3);
  const Scene scene = generateScene(library, SceneOptions{}, ScenePreset::kRandom, random);
  ASSERT_EQ(scene.objects.size(), 3u);
  EXPECT_TRUE(scene.objects[0].position_m.isZero());
  EXPECT_DOUBLE_EQ(scene.objects[1].position_m.x(), 1.0);
  EXPECT_DOUBLE_EQ(scene.objects[2].position_m.x(), 2.0);
  EXPECT_DOUBLE_EQ(scene.objects[1].position_m.y(), -scene.objects[2].position_m.y());
  EXPECT_DOUBLE_EQ(scene.objects[1].position_m.z(), 0.0);
}

TEST(SceneTest, SidewaysOffsetIsNormalWithSigma) {
  ObjectLibrary library(std::make_shared<BoxCatalog>(), 0);
  SceneOptions options;
  options.lateral_sigma_m = 0.5;
  const int n = 4000;
  double sum = 0.0, sum_sq = 0.0;
  for (int seed = 0; seed < n; ++seed) {
    RandomSource random(seed);
    const double y =
        generateScene(library, options, ScenePreset::kRandom, random).objects[1].position_m.y();
    sum += y;
    sum_sq += y * y;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.0, 4.0 * 0.5 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sum_sq / n - mean * mean), 0.5, 0.03);
}

TEST(SceneTest, ChoosesByCategoryAndById) {
  ObjectLibrary library(std::make_shared<BoxCatalog>(), 0);
  SceneOptions options;
  options.categories = {"table"};
  options.num_objects = 4;
  RandomSource random(1);
  const Scene tables = generateScene(library, options, ScenePreset::kRandom, random);
  ASSERT_EQ(tables.objects.size(), 4u);
  for (const SceneObject& object : tables.objects) EXPECT_EQ(object.model->info.id, "box/t");
  EXPECT_DOUBLE_EQ(tables.objects[3].position_m.x(), 3.0);

  options.object_ids = {"box/b", "box/a"};
  const Scene chosen = generateScene(library, options, ScenePreset::kRandom, random);
  ASSERT_EQ(chosen.objects.size(), 2u);
  EXPECT_EQ(chosen.objects[0].model->info.id, "box/b");
  EXPECT_EQ(chosen.objects[1].model->info.id, "box/a");
}

TEST(SceneTest, TwoChairsPresetIsTwoCopiesTwoUnitsApart) {
  ObjectLibrary library(std::make_shared<BoxCatalog>(), 0);
  RandomSource random(5);
  const Scene scene = generateScene(library, SceneOptions{}, ScenePreset::kTwoChairs, random);
  ASSERT_EQ(scene.objects.size(), 2u);
  EXPECT_EQ(scene.objects[0].model, scene.objects[1].model);
  EXPECT_EQ(scene.objects[0].model->info.category, "chair");
  EXPECT_TRUE(scene.objects[1].position_m.isApprox(Eigen::Vector3d(2, 0, 0)));
  RandomSource again(5);
  EXPECT_EQ(generateScene(library, SceneOptions{}, ScenePreset::kTwoTables, again)
                .objects[0]
                .model->info.id,
            "box/t");
}

TEST(SceneTest, RejectsUnknownIdsCategoriesAndPresets) {
  ObjectLibrary library(std::make_shared<BoxCatalog>(), 0);
  RandomSource random(0);
  SceneOptions options;
  options.object_ids = {"../../etc/passwd"};
  EXPECT_THROW(generateScene(library, options, ScenePreset::kRandom, random), InvalidArgumentError);
  options.object_ids.clear();
  options.categories = {"spaceship"};
  EXPECT_THROW(generateScene(library, options, ScenePreset::kRandom, random), InvalidArgumentError);
  options.categories.clear();
  options.num_objects = 9;
  EXPECT_THROW(generateScene(library, options, ScenePreset::kRandom, random), InvalidArgumentError);
  EXPECT_THROW(parseScenePreset("three_chairs"), InvalidArgumentError);
  for (auto preset : {ScenePreset::kRandom, ScenePreset::kTwoChairs, ScenePreset::kTwoTables}) {
    EXPECT_EQ(parseScenePreset(toString(preset)), preset);
  }
}

}  // namespace
}  // namespace occlusion_env
