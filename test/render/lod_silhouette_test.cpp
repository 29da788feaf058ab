// The level-of-detail meshes must keep each object's silhouette: IoU >= 0.98 against the full
// mesh at 256x256, on every chair of the Sweet Home 3D catalogue and on every embedded object.
#include <gtest/gtest.h>

#include <filesystem>

#include "occlusion_env/geometry/camera.hpp"
#include "occlusion_env/render/lod_quality.hpp"
#include "occlusion_env/render/osmesa_renderer.hpp"
#include "occlusion_env/scene/object_library.hpp"

namespace occlusion_env {
namespace {

constexpr double kMinIou = 0.98;
constexpr std::size_t kLodBudget = 5000;  // the environment's default

/// Checks every object of `category` ("" = all) from eight views; returns how many were checked.
int checkCatalog(std::shared_ptr<const ObjectCatalog> catalog, const std::string& category) {
  ObjectLibrary library(catalog, kLodBudget);
  // The object's diagonal (1) spans about half of the image. The worst IoU depends on this
  // distance: BENCHMARKS.md ("LOD budget") has it at 1.0 and 2.5 too (occlusion_lod_report).
  const SphericalCamera camera(1.6, 1.3);
  auto renderer = makeOsMesaRenderer(CameraIntrinsics::fromFieldOfView(256, 256, M_PI / 3.0));
  const std::vector<SphericalPose> views = silhouetteCheckViews();
  RenderBuffers full, lod;
  int checked = 0;
  const std::vector<std::string> ids =
      category.empty() ? std::vector<std::string>{} : catalog->idsInCategory(category);
  std::vector<std::string> all_ids;
  for (const ObjectInfo& info : catalog->objects()) all_ids.push_back(info.id);
  for (const std::string& id : category.empty() ? all_ids : ids) {
    const auto model = library.get(id);
    EXPECT_LE(model->render.triangleCount(), kLodBudget) << id;
    const double worst =
        worstSilhouetteIou(*renderer, model->full, model->render, camera, views, full, lod);
    EXPECT_GE(worst, kMinIou) << id << " (" << model->full.triangleCount() << " -> "
                              << model->render.triangleCount() << " triangles)";
    ++checked;
  }
  return checked;
}

TEST(LodSilhouetteTest, IouIsOneForTheSameMeshAndFallsWithTheArea) {
  ObjectLibrary library(makeEmbeddedCatalog(), 0);
  const Mesh& mesh = library.get(library.catalog().objects().front().id)->full;
  Mesh shrunk = mesh;
  for (Eigen::Vector3f& p : shrunk.positions) p *= 0.9f;  // 0.81 of the silhouette area
  auto renderer = makeOsMesaRenderer(CameraIntrinsics::fromFieldOfView(256, 256, M_PI / 3.0));
  const SphericalCamera camera(1.6, 1.3);
  const std::vector<SphericalPose> views = silhouetteCheckViews();
  ASSERT_EQ(views.size(), 8u);
  RenderBuffers a, b;
  EXPECT_EQ(worstSilhouetteIou(*renderer, mesh, mesh, camera, views, a, b), 1.0);
  const double iou = worstSilhouetteIou(*renderer, mesh, shrunk, camera, views, a, b);
  EXPECT_GT(iou, 0.70);
  EXPECT_LT(iou, 0.90);
  EXPECT_EQ(worstSilhouetteIou(*renderer, mesh, shrunk, camera, {}, a, b), 1.0);
}

TEST(LodSilhouetteTest, EveryCatalogueChairKeepsItsSilhouette) {
  if (defaultSweetHome3DCatalogPaths().empty()) GTEST_SKIP() << "sweethome3d-furniture missing";
  const int checked =
      checkCatalog(makeSweetHome3DCatalog(defaultSweetHome3DCatalogPaths()), "chair");
  EXPECT_GE(checked, 50);
}

TEST(LodSilhouetteTest, EveryEmbeddedObjectKeepsItsSilhouette) {
  EXPECT_GE(checkCatalog(makeEmbeddedCatalog(), ""), 10);
}

}  // namespace
}  // namespace occlusion_env
