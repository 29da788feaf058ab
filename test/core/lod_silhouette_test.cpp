// The level-of-detail meshes must keep each object's silhouette: IoU >= 0.98 against the full
// mesh at 256x256, on every chair of the Sweet Home 3D catalogue and on every embedded object.
#include <gtest/gtest.h>

#include <filesystem>

#include "occlusion_env/core/camera.hpp"
#include "occlusion_env/core/object_library.hpp"
#include "occlusion_env/core/renderer.hpp"

namespace occlusion_env {
namespace {

constexpr double kMinIou = 0.98;
constexpr std::size_t kLodBudget = 5000;  // the environment's default

/// IoU of the object's silhouettes, full against LOD, seen from `pose`.
double silhouetteIou(Renderer& renderer, const ObjectModel& model, const SphericalPose& pose,
                     const SphericalCamera& camera, RenderBuffers& full, RenderBuffers& lod) {
  const Eigen::Isometry3d world_from_optical = camera.worldFromOptical(pose);
  renderer.setScene({{&model.full, Eigen::Isometry3d::Identity()}});
  renderer.render(world_from_optical, full);
  renderer.setScene({{&model.render, Eigen::Isometry3d::Identity()}});
  renderer.render(world_from_optical, lod);
  const cv::Mat a = full.amodal_bits != 0, b = lod.amodal_bits != 0;
  const int intersection = cv::countNonZero(a & b), united = cv::countNonZero(a | b);
  return united == 0 ? 1.0 : static_cast<double>(intersection) / united;
}

/// Checks every object of `category` ("" = all) from eight views; returns how many were checked.
int checkCatalog(std::shared_ptr<const ObjectCatalog> catalog, const std::string& category) {
  ObjectLibrary library(catalog, kLodBudget);
  // The object (unit diagonal) fills about half of the image: stricter than the environment's view.
  const SphericalCamera camera(1.6, 1.3);
  auto renderer = makeOsMesaRenderer(CameraIntrinsics::fromFieldOfView(256, 256, M_PI / 3.0));
  RenderBuffers full, lod;
  int checked = 0;
  const std::vector<std::string> ids =
      category.empty() ? std::vector<std::string>{} : catalog->idsInCategory(category);
  std::vector<std::string> all_ids;
  for (const ObjectInfo& info : catalog->objects()) all_ids.push_back(info.id);
  for (const std::string& id : category.empty() ? all_ids : ids) {
    const auto model = library.get(id);
    EXPECT_LE(model->render.triangleCount(), kLodBudget) << id;
    double worst = 1.0;
    for (double azimuth : {0.0, 0.8, 1.6, 2.4, 3.1, -0.8, -1.6, -2.4}) {
      const double elevation = azimuth > 0 ? 0.0 : 0.5;
      worst = std::min(worst,
                       silhouetteIou(*renderer, *model, {azimuth, elevation}, camera, full, lod));
    }
    EXPECT_GE(worst, kMinIou) << id << " (" << model->full.triangleCount() << " -> "
                              << model->render.triangleCount() << " triangles)";
    ++checked;
  }
  return checked;
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
