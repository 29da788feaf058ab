// The horizontal flip the trainer uses for augmentation, with its label transform
// (dataset/labels.hpp), gives the label the renderer and the gradient compute for the mirrored
// scene: real (asymmetric) embedded objects, mirrored about the vertical plane through the camera
// and the scene centre, seen from the same pose.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "occlusion_env/dataset/labels.hpp"
#include "occlusion_env/occlusion/occlusion.hpp"
#include "occlusion_env/occlusion/occlusion_gradient.hpp"
#include "occlusion_env/render/osmesa_renderer.hpp"
#include "occlusion_env/scene/object_library.hpp"

namespace occlusion_env {
namespace dataset {
namespace {

Mesh mirrored(const Mesh& mesh) {
  Mesh out = mesh;
  for (Eigen::Vector3f& p : out.positions) p.y() = -p.y();
  for (std::size_t t = 0; t + 2 < out.indices.size(); t += 3)
    std::swap(out.indices[t + 1], out.indices[t + 2]);
  return out;
}

double angleBetween(const Direction& a, const Direction& b) {
  return std::abs(std::remainder(a.angle_rad - b.angle_rad, 2.0 * M_PI));
}

TEST(FlipTest, FlippedImageAndFlippedLabelMatchTheMirroredScene) {
  ObjectLibrary library(makeCatalog({}), 5000);
  const std::vector<std::string> ids = {library.catalog().objects()[0].id,
                                        library.catalog().objects()[3].id,
                                        library.catalog().objects()[5].id};
  const std::vector<Eigen::Vector3d> positions = {
      {0.0, 0.0, 0.0}, {1.0, 0.45, 0.0}, {2.0, -0.45, 0.0}};
  std::vector<Mesh> meshes, mirrored_meshes;
  for (const std::string& id : ids) {
    meshes.push_back(library.get(id)->render);
    mirrored_meshes.push_back(mirrored(meshes.back()));
  }
  const int size = 128;
  const CameraIntrinsics intrinsics = CameraIntrinsics::fromFieldOfView(size, size, M_PI / 3.0);
  const SphericalCamera camera(4.0, 1.3962634016);
  AnalyticOcclusionGradient gradient;
  int checked = 0;
  for (const SphericalPose pose :
       {SphericalPose{0.0, 0.0}, SphericalPose{0.0, 0.12}, SphericalPose{0.0, -0.08}}) {
    auto renderer = makeOsMesaRenderer(intrinsics);
    std::vector<PlacedMesh> scene, mirror_scene;
    for (std::size_t k = 0; k < meshes.size(); ++k) {
      PlacedMesh placed{&meshes[k], Eigen::Isometry3d(Eigen::Translation3d(positions[k]))};
      Eigen::Vector3d mirrored_position = positions[k];
      mirrored_position.y() = -mirrored_position.y();
      scene.push_back(placed);
      mirror_scene.push_back(
          {&mirrored_meshes[k], Eigen::Isometry3d(Eigen::Translation3d(mirrored_position))});
    }
    // The camera sits on the mirror plane (azimuth 0: the x-z plane).
    RenderBuffers original, mirror;
    renderer->setScene(scene);
    renderer->render(camera.worldFromOptical(pose), original);
    renderer->setScene(mirror_scene);
    renderer->render(camera.worldFromOptical(pose), mirror);
    SCOPED_TRACE("elevation " + std::to_string(pose.elevation_rad));

    // The mirrored scene's images are the flipped images (up to rasterisation ties on edges).
    cv::Mat flipped_bits, flipped_rgb;
    cv::flip(original.amodal_bits, flipped_bits, 1);
    cv::flip(original.rgb, flipped_rgb, 1);
    const int differing_bits = cv::countNonZero(flipped_bits != mirror.amodal_bits);
    EXPECT_LT(differing_bits, size * size / 200) << "amodal silhouettes";
    const std::int64_t occlusion = computeOcclusion(original.amodal_bits, 3).total_pixels;
    const std::int64_t mirrored_occlusion = computeOcclusion(mirror.amodal_bits, 3).total_pixels;
    ASSERT_GT(occlusion, 0) << "the test scene must show occlusion";
    EXPECT_NEAR(mirrored_occlusion, occlusion, 0.02 * occlusion + 5);

    // The label of the flipped image is the label of the mirrored scene.
    const GradientResult g = gradient.compute(original, 3, intrinsics, camera, pose);
    const GradientResult g_mirror = gradient.compute(mirror, 3, intrinsics, camera, pose);
    ASSERT_TRUE(g.valid && g_mirror.valid);
    const Direction label = *directionOf(-g.gradient.x(), -g.gradient.y());
    const Direction mirror_label = *directionOf(-g_mirror.gradient.x(), -g_mirror.gradient.y());
    EXPECT_LT(angleBetween(flippedHorizontally(label), mirror_label), 0.05)
        << "flipped " << flippedHorizontally(label).angle_rad << ", mirrored scene "
        << mirror_label.angle_rad;
    // Without the transform the label would be wrong (unless it points straight up or down).
    if (std::abs(label.cos) > 0.2) EXPECT_GT(angleBetween(label, mirror_label), 0.3);
    ++checked;
  }
  EXPECT_EQ(checked, 3);
}

TEST(FlipTest, LabelTransformIsAnInvolutionOnUnitVectors) {
  for (double angle = -3.0; angle <= 3.0; angle += 0.37) {
    const Direction d = *directionOf(std::cos(angle), std::sin(angle));
    const Direction back = flippedHorizontally(flippedHorizontally(d));
    EXPECT_NEAR(back.sin, d.sin, 1e-15);
    EXPECT_NEAR(back.cos, d.cos, 1e-15);
    EXPECT_NEAR(std::remainder(flippedHorizontally(d).angle_rad - (M_PI - angle), 2 * M_PI), 0.0,
                1e-12);
  }
  EXPECT_FALSE(directionOf(0.0, 0.0).has_value());
  EXPECT_FALSE(directionOf(std::nan(""), 1.0).has_value());
}

}  // namespace
}  // namespace dataset
}  // namespace occlusion_env
