#include "occlusion_env/render/osmesa_renderer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <thread>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "render/osmesa/osmesa_library.hpp"

namespace occlusion_env {
namespace {

constexpr int kSize = 128;                // [px] square test images
constexpr double kDepthTolerance = 1e-3;  // [m]

// 90 degree horizontal field of view, principal point at the centre (ROS convention).
CameraIntrinsics testIntrinsics(int width = kSize, int height = kSize) {
  CameraIntrinsics k;
  k.width = width;
  k.height = height;
  k.fx = k.fy = 0.5 * width;
  k.cx = 0.5 * (width - 1);
  k.cy = 0.5 * (height - 1);
  return k;
}

// Optical frame (z forward, x right, y down) at `position` looking at `target`, world z up.
Eigen::Isometry3d lookAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - position).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << x, z.cross(x), z;
  pose.translation() = position;
  return pose;
}

// The camera at world (distance, 0, 0) looking along world -x at the origin.
Eigen::Isometry3d cameraOnPlusX(double distance_m) {
  return lookAt(Eigen::Vector3d(distance_m, 0, 0), Eigen::Vector3d::Zero());
}

// Axis-aligned box of the given half extents [m], centred at the object origin.
Mesh makeBox(const Eigen::Vector3f& half, const Eigen::Vector3f& color) {
  Mesh mesh;
  for (int corner = 0; corner < 8; ++corner) {
    mesh.positions.emplace_back((corner & 1) ? half.x() : -half.x(),
                                (corner & 2) ? half.y() : -half.y(),
                                (corner & 4) ? half.z() : -half.z());
    mesh.colors.push_back(color);
  }
  // Two triangles per face, deliberately of mixed winding.
  mesh.indices = {0, 1, 3, 0, 3, 2, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                  2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 3, 7, 1, 7, 5};
  return mesh;
}

Mesh makeCube(float half_m) {
  return makeBox(Eigen::Vector3f::Constant(half_m), Eigen::Vector3f(0.8f, 0.4f, 0.2f));
}

PlacedMesh place(const Mesh& mesh, const Eigen::Vector3d& position) {
  PlacedMesh placed;
  placed.mesh = &mesh;
  placed.world_from_object = Eigen::Translation3d(position);
  return placed;
}

bool sameBytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

// Mean (column, row) of the pixels whose instance equals `instance`.
Eigen::Vector2d instanceCentroid(const cv::Mat& instance_mask, int instance) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int count = 0;
  for (int row = 0; row < instance_mask.rows; ++row) {
    for (int col = 0; col < instance_mask.cols; ++col) {
      if (instance_mask.at<std::uint8_t>(row, col) == instance) {
        sum += Eigen::Vector2d(col, row);
        ++count;
      }
    }
  }
  EXPECT_GT(count, 0);
  return count > 0 ? Eigen::Vector2d(sum / count) : Eigen::Vector2d(-1, -1);
}

TEST(OsMesaRendererTest, BoxDepthAtTheCentreAndNaNBackground) {
  const auto renderer = makeOsMesaRenderer(testIntrinsics());
  EXPECT_EQ(renderer->name(), "osmesa");
  const Mesh box = makeCube(0.5f);
  renderer->setScene({place(box, Eigen::Vector3d::Zero())});
  RenderBuffers out;
  renderer->render(cameraOnPlusX(3.0), out);

  ASSERT_EQ(out.rgb.type(), CV_8UC3);
  ASSERT_EQ(out.depth.type(), CV_32FC1);
  ASSERT_EQ(out.instance.type(), CV_8UC1);
  ASSERT_EQ(out.amodal_bits.type(), CV_8UC1);
  ASSERT_EQ(out.rgb.size(), cv::Size(kSize, kSize));
  ASSERT_EQ(out.object_depth.size(), 1u);

  const int c = kSize / 2;
  EXPECT_NEAR(out.depth.at<float>(c, c), 2.5, kDepthTolerance);  // front face at x = 0.5
  EXPECT_TRUE(std::isnan(out.depth.at<float>(0, 0)));
  EXPECT_EQ(out.instance.at<std::uint8_t>(c, c), 1);
  EXPECT_EQ(out.instance.at<std::uint8_t>(0, 0), 0);
  EXPECT_EQ(out.amodal_bits.at<std::uint8_t>(0, 0), 0);
  const cv::Vec3b lit = out.rgb.at<cv::Vec3b>(c, c);
  EXPECT_GT(lit[0], lit[2]);  // an orange box stays orange (RGB order)
  EXPECT_EQ(out.rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 0));
}

TEST(OsMesaRendererTest, NearBoxHidesFarBoxButNotItsAmodalSilhouette) {
  const auto renderer = makeOsMesaRenderer(testIntrinsics());
  const Mesh far_box = makeCube(0.5f);   // object 0, front face 2.5 m from the camera
  const Mesh near_box = makeCube(0.1f);  // object 1, front face 1.4 m from the camera
  renderer->setScene(
      {place(far_box, Eigen::Vector3d::Zero()), place(near_box, Eigen::Vector3d(1.5, 0, 0))});
  RenderBuffers out;
  renderer->render(cameraOnPlusX(3.0), out);
  ASSERT_EQ(out.object_depth.size(), 2u);

  // The centre: the near box is visible, both objects cover it.
  const int c = kSize / 2;
  EXPECT_EQ(out.instance.at<std::uint8_t>(c, c), 2);
  EXPECT_EQ(out.amodal_bits.at<std::uint8_t>(c, c), 0b11);
  EXPECT_NEAR(out.depth.at<float>(c, c), 1.4, kDepthTolerance);
  EXPECT_NEAR(out.object_depth[0].at<float>(c, c), 2.5, kDepthTolerance);
  EXPECT_NEAR(out.object_depth[1].at<float>(c, c), 1.4, kDepthTolerance);

  // Beside the near box (~4.6 px half width) but on the far box (~12.8 px half width).
  const int side = c + 9;
  EXPECT_EQ(out.instance.at<std::uint8_t>(c, side), 1);
  EXPECT_EQ(out.amodal_bits.at<std::uint8_t>(c, side), 0b01);
  EXPECT_NEAR(out.object_depth[0].at<float>(c, side), 2.5, kDepthTolerance);
  EXPECT_EQ(out.object_depth[1].at<float>(c, side), std::numeric_limits<float>::infinity());

  // Background: no object, +inf object depths, NaN depth.
  EXPECT_EQ(out.amodal_bits.at<std::uint8_t>(2, 2), 0);
  EXPECT_EQ(out.object_depth[0].at<float>(2, 2), std::numeric_limits<float>::infinity());
  EXPECT_TRUE(std::isnan(out.depth.at<float>(2, 2)));

  // Everywhere: the visible object's own depth equals the scene depth, and the bits agree with
  // the object depths; the far box is hidden exactly where the near box covers it.
  int hidden_pixels = 0;
  for (int row = 0; row < kSize; ++row) {
    for (int col = 0; col < kSize; ++col) {
      const int instance = out.instance.at<std::uint8_t>(row, col);
      const int bits = out.amodal_bits.at<std::uint8_t>(row, col);
      for (int k = 0; k < 2; ++k) {
        const bool covered = std::isfinite(out.object_depth[k].at<float>(row, col));
        EXPECT_EQ(covered, ((bits >> k) & 1) != 0);
      }
      if (instance > 0) {
        EXPECT_TRUE((bits >> (instance - 1)) & 1);
        EXPECT_NEAR(out.object_depth[instance - 1].at<float>(row, col),
                    out.depth.at<float>(row, col), 1e-5);
      } else {
        EXPECT_EQ(bits, 0);
      }
      if (bits == 0b11) {
        EXPECT_EQ(instance, 2);
        ++hidden_pixels;
      }
    }
  }
  EXPECT_GT(hidden_pixels, 50);
}

TEST(OsMesaRendererTest, WorldUpIsImageTopAndCameraLeftIsImageLeft) {
  // Looking along world -x from +x, the camera's left is world -y and its up is world +z.
  const Eigen::Isometry3d world_from_optical = cameraOnPlusX(3.0);
  ASSERT_TRUE(world_from_optical.linear().col(0).isApprox(Eigen::Vector3d(0, 1, 0)));
  ASSERT_TRUE(world_from_optical.linear().col(1).isApprox(Eigen::Vector3d(0, 0, -1)));

  const auto renderer = makeOsMesaRenderer(testIntrinsics());
  const Mesh up_box = makeCube(0.1f);
  const Mesh left_box = makeCube(0.1f);
  renderer->setScene(
      {place(up_box, Eigen::Vector3d(0, 0, 1.5)), place(left_box, Eigen::Vector3d(0, -1.5, 0))});
  RenderBuffers out;
  renderer->render(world_from_optical, out);

  const Eigen::Vector2d up = instanceCentroid(out.instance, 1);
  const Eigen::Vector2d left = instanceCentroid(out.instance, 2);
  EXPECT_LT(up.y(), kSize / 4.0);               // top rows
  EXPECT_NEAR(up.x(), (kSize - 1) / 2.0, 1.0);  // horizontally centred
  EXPECT_LT(left.x(), kSize / 4.0);             // left columns
  EXPECT_NEAR(left.y(), (kSize - 1) / 2.0, 1.0);
}

TEST(OsMesaRendererTest, PixelsMatchTheIntrinsicsProjection) {
  // Non-square image, off-centre principal point, different focal lengths.
  CameraIntrinsics k = testIntrinsics(160, 120);
  k.fx = 100.0;
  k.fy = 90.0;
  k.cx = 70.0;
  k.cy = 65.0;
  const auto renderer = makeOsMesaRenderer(k);
  const Eigen::Isometry3d world_from_optical =
      lookAt(Eigen::Vector3d(2.0, 1.0, 0.7), Eigen::Vector3d(0.1, -0.2, 0.1));
  const Mesh dot = makeCube(0.05f);
  const std::vector<Eigen::Vector3d> points = {
      {0.0, 0.0, 0.0}, {0.3, -0.4, 0.5}, {-0.2, 0.5, -0.3}, {0.4, 0.3, 0.2}};
  std::vector<PlacedMesh> scene;
  for (const Eigen::Vector3d& point : points) scene.push_back(place(dot, point));
  renderer->setScene(scene);
  RenderBuffers out;
  renderer->render(world_from_optical, out);

  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d optical = world_from_optical.inverse() * points[i];
    const Eigen::Vector2d expected = k.project(optical);
    const Eigen::Vector2d actual = instanceCentroid(out.instance, static_cast<int>(i) + 1);
    EXPECT_LT((actual - expected).norm(), 1.0)
        << "point " << i << " expected " << expected.transpose() << " got " << actual.transpose();
  }
}

TEST(OsMesaRendererTest, TwoRenderersInterleaveOnOneThread) {
  const Mesh box = makeCube(0.5f);
  const Mesh small_box = makeCube(0.2f);
  const auto first = makeOsMesaRenderer(testIntrinsics());
  first->setScene({place(box, Eigen::Vector3d::Zero())});
  RenderBuffers first_reference;
  first->render(cameraOnPlusX(3.0), first_reference);

  const auto second = makeOsMesaRenderer(testIntrinsics(96, 64));
  second->setScene(
      {place(small_box, Eigen::Vector3d(0, 0.3, 0)), place(box, Eigen::Vector3d(-2, 0, 0))});
  RenderBuffers second_reference;
  second->render(cameraOnPlusX(2.0), second_reference);
  EXPECT_EQ(second_reference.rgb.size(), cv::Size(96, 64));
  ASSERT_EQ(second_reference.object_depth.size(), 2u);

  {  // A third renderer coming and going leaves the others working.
    const auto third = makeOsMesaRenderer(testIntrinsics(32, 32));
    third->setScene({});
    RenderBuffers unused;
    third->render(cameraOnPlusX(1.0), unused);
    EXPECT_TRUE(unused.object_depth.empty());
  }
  for (int round = 0; round < 3; ++round) {
    RenderBuffers a, b;
    first->render(cameraOnPlusX(3.0), a);
    second->render(cameraOnPlusX(2.0), b);
    EXPECT_TRUE(sameBytes(a.depth, first_reference.depth));
    EXPECT_TRUE(sameBytes(a.rgb, first_reference.rgb));
    EXPECT_TRUE(sameBytes(b.depth, second_reference.depth));
    EXPECT_TRUE(sameBytes(b.instance, second_reference.instance));
    EXPECT_TRUE(sameBytes(b.amodal_bits, second_reference.amodal_bits));
  }
  EXPECT_NEAR(first_reference.depth.at<float>(kSize / 2, kSize / 2), 2.5, kDepthTolerance);
}

// Renderers on several threads at once (each thread on its own copy of libOSMesa, see
// osmesa_library.hpp) render what one renderer renders alone, and one made on a thread that has
// ended can be destroyed from another while a renderer there keeps working.
TEST(OsMesaRendererTest, RenderersOnSeveralThreadsMatchOneThread) {
  const Mesh far_box = makeCube(0.5f);
  const Mesh near_box = makeCube(0.2f);
  const std::vector<PlacedMesh> scene = {place(far_box, Eigen::Vector3d::Zero()),
                                         place(near_box, Eigen::Vector3d(1.0, 0.3, 0.2))};
  const Eigen::Isometry3d pose = lookAt(Eigen::Vector3d(3.0, 1.0, 1.0), Eigen::Vector3d::Zero());
  const auto local = makeOsMesaRenderer(testIntrinsics());
  local->setScene(scene);
  RenderBuffers reference;
  local->render(pose, reference);

  constexpr int kThreads = 3;
  std::vector<std::unique_ptr<Renderer>> renderers(kThreads);
  std::vector<RenderBuffers> results(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      renderers[t] = makeOsMesaRenderer(testIntrinsics());
      renderers[t]->setScene(scene);
      for (int round = 0; round < 20; ++round) renderers[t]->render(pose, results[t]);
    });
  }
  for (auto& thread : threads) thread.join();
  for (int t = 0; t < kThreads; ++t) {
    EXPECT_TRUE(sameBytes(results[t].rgb, reference.rgb)) << t;
    EXPECT_TRUE(sameBytes(results[t].depth, reference.depth)) << t;
    EXPECT_TRUE(sameBytes(results[t].instance, reference.instance)) << t;
    EXPECT_TRUE(sameBytes(results[t].amodal_bits, reference.amodal_bits)) << t;
  }
  renderers.clear();  // destroyed here, not on the threads that made them
  RenderBuffers again;
  local->render(pose, again);
  EXPECT_TRUE(sameBytes(again.rgb, reference.rgb));
  EXPECT_TRUE(sameBytes(again.amodal_bits, reference.amodal_bits));
}

// Two threads holding leases at once get different copies; one thread keeps its copy.
TEST(OsMesaLibraryTest, ThreadsRenderingAtOnceGetCopiesOfTheirOwn) {
  const char* shared = std::getenv("OCCLUSION_ENV_SHARED_LLVMPIPE");
  if (shared != nullptr && std::string(shared) == "1") GTEST_SKIP() << "copies turned off";
  const osmesa::OsMesaLease here(std::this_thread::get_id()), again(std::this_thread::get_id());
  EXPECT_EQ(&here.library(), &again.library());
  const osmesa::OsMesaLibrary* there = nullptr;
  std::thread([&] {
    const osmesa::OsMesaLease lease(std::this_thread::get_id());
    there = &lease.library();
  }).join();
  EXPECT_NE(there, &here.library());
  EXPECT_NE(there->create_context_attribs, here.library().create_context_attribs);
}

TEST(OsMesaRendererTest, RejectsTooManyObjectsAndMissingMeshes) {
  const auto renderer = makeOsMesaRenderer(testIntrinsics(32, 32));
  const Mesh box = makeCube(0.3f);
  std::vector<PlacedMesh> scene(kMaxSceneObjects, place(box, Eigen::Vector3d::Zero()));
  EXPECT_NO_THROW(renderer->setScene(scene));
  scene.push_back(place(box, Eigen::Vector3d::Zero()));
  EXPECT_THROW(renderer->setScene(scene), InvalidArgumentError);
  EXPECT_THROW(renderer->setScene({PlacedMesh{}}), InvalidArgumentError);
  const Mesh empty;
  EXPECT_THROW(renderer->setScene({place(empty, Eigen::Vector3d::Zero())}), InvalidArgumentError);

  // The accepted eight-object scene is still in place and renders all eight bits.
  RenderBuffers out;
  renderer->render(cameraOnPlusX(2.0), out);
  ASSERT_EQ(out.object_depth.size(), static_cast<std::size_t>(kMaxSceneObjects));
  EXPECT_EQ(out.amodal_bits.at<std::uint8_t>(16, 16), 0xFF);
}

TEST(OsMesaRendererTest, RepeatedRendersAreBitIdenticalAndReuseBuffers) {
  const auto renderer = makeOsMesaRenderer(testIntrinsics());
  const Mesh far_box = makeCube(0.5f);
  const Mesh near_box = makeCube(0.2f);
  renderer->setScene(
      {place(far_box, Eigen::Vector3d::Zero()), place(near_box, Eigen::Vector3d(1.0, 0.3, 0.2))});
  const Eigen::Isometry3d pose = lookAt(Eigen::Vector3d(3.0, 1.0, 1.0), Eigen::Vector3d::Zero());
  RenderBuffers first;
  renderer->render(pose, first);
  RenderBuffers again;
  renderer->render(pose, again);
  const std::uint8_t* depth_data = again.depth.data;
  const std::uint8_t* object_depth_data = again.object_depth[1].data;
  renderer->render(pose, again);
  EXPECT_EQ(again.depth.data, depth_data);  // no reallocation
  EXPECT_EQ(again.object_depth[1].data, object_depth_data);

  EXPECT_TRUE(sameBytes(first.rgb, again.rgb));
  EXPECT_TRUE(sameBytes(first.depth, again.depth));
  EXPECT_TRUE(sameBytes(first.instance, again.instance));
  EXPECT_TRUE(sameBytes(first.amodal_bits, again.amodal_bits));
  ASSERT_EQ(first.object_depth.size(), again.object_depth.size());
  for (std::size_t k = 0; k < first.object_depth.size(); ++k) {
    EXPECT_TRUE(sameBytes(first.object_depth[k], again.object_depth[k]));
  }
}

// Renders reuse their buffers and rewrite only the footprints of this render and the last one:
// the result must equal a render into fresh buffers, also when objects leave the view, cross the
// near plane, or the scene's object count changes, and with two buffers used in turn.
TEST(OsMesaRendererTest, ReusedBuffersMatchFreshOnesAsTheFootprintsChange) {
  const auto renderer = makeOsMesaRenderer(testIntrinsics(96, 80));
  const Mesh big = makeCube(0.5f);
  const Mesh small = makeCube(0.15f);
  const std::vector<PlacedMesh> three = {place(big, Eigen::Vector3d::Zero()),
                                         place(small, Eigen::Vector3d(1.0, 0.4, 0.2)),
                                         place(small, Eigen::Vector3d(-1.5, -1.2, 0.0))};
  const std::vector<std::vector<PlacedMesh>> scenes = {
      three, {three[0], three[1]}, three, {three[2]}, three};
  const std::vector<Eigen::Isometry3d> poses = {
      cameraOnPlusX(3.0),
      lookAt(Eigen::Vector3d(3.0, 1.0, 1.0), Eigen::Vector3d::Zero()),
      lookAt(Eigen::Vector3d(10.0, 0.0, 0.0), Eigen::Vector3d(4.0, 8.0, 0.0)),  // all beside
      lookAt(Eigen::Vector3d(0.2, 0.1, 0.0), Eigen::Vector3d(-3.0, 0.0, 0.0)),  // inside the box
      lookAt(Eigen::Vector3d(2.0, -2.0, 0.5), Eigen::Vector3d(0.0, -1.0, 0.0)),
      cameraOnPlusX(6.0)};
  RenderBuffers reused[2];
  int renders = 0, empty_footprints = 0, whole_footprints = 0;
  for (const std::vector<PlacedMesh>& scene : scenes) {
    renderer->setScene(scene);
    for (const Eigen::Isometry3d& pose : poses) {
      RenderBuffers& out = reused[renders++ % 2];
      renderer->render(pose, out);
      RenderBuffers fresh;
      renderer->render(pose, fresh);
      EXPECT_EQ(out.footprint, fresh.footprint);
      if (out.footprint.empty()) ++empty_footprints;
      if (out.footprint == cv::Rect(0, 0, 96, 80)) ++whole_footprints;
      EXPECT_TRUE(sameBytes(out.rgb, fresh.rgb)) << "render " << renders;
      EXPECT_TRUE(sameBytes(out.depth, fresh.depth)) << "render " << renders;
      EXPECT_TRUE(sameBytes(out.instance, fresh.instance)) << "render " << renders;
      EXPECT_TRUE(sameBytes(out.amodal_bits, fresh.amodal_bits)) << "render " << renders;
      ASSERT_EQ(out.object_depth.size(), scene.size());
      for (std::size_t k = 0; k < scene.size(); ++k) {
        EXPECT_TRUE(sameBytes(out.object_depth[k], fresh.object_depth[k])) << "render " << renders;
      }
      // Outside the footprint: background only.
      cv::Mat outside(out.amodal_bits.size(), CV_8UC1, cv::Scalar(255));
      outside(out.footprint).setTo(0);
      EXPECT_EQ(cv::countNonZero(out.amodal_bits & outside), 0);
    }
  }
  EXPECT_GT(empty_footprints, 0);
  EXPECT_GT(whole_footprints, 0);
}

// A tiled surface (SceneBackground::tiled): each cell in its colour, lit like the objects, at the
// plane's depth; seen from behind it is not drawn; no instance, no silhouette.
TEST(OsMesaRendererTest, TiledSurfaceShowsItsCellsFromTheFrontOnly) {
  auto renderer = makeOsMesaRenderer(testIntrinsics());
  renderer->setScene({});
  SceneBackground background;
  TiledSurface wall;  // the plane x = -1, y and z in [-2, 2], facing +x
  wall.origin = Eigen::Vector3f(-1, -2, -2);
  wall.step_u = Eigen::Vector3f(0, 2, 0);
  wall.step_v = Eigen::Vector3f(0, 0, 2);
  wall.cells_u = wall.cells_v = 2;
  wall.colors = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5f, 0.5f, 0.5f}};
  background.tiled.push_back(wall);
  background.lighting.headlight = false;
  background.lighting.ambient = 1.0f;
  background.lighting.diffuse = 0.0f;
  renderer->setBackground(background);
  RenderBuffers out;
  renderer->render(cameraOnPlusX(2.0), out);  // image right = world +y, image down = world -z
  const int grey = static_cast<int>(std::pow(0.5, 1.0 / 2.2) * 255.0 + 0.5);
  const struct {
    int u, v;
    cv::Vec3b rgb;
  } cells[] = {{32, 96, {255, 0, 0}},
               {96, 96, {0, 255, 0}},
               {32, 32, {0, 0, 255}},
               {96, 32, cv::Vec3b(grey, grey, grey)}};
  for (const auto& cell : cells) {
    const cv::Vec3b rgb = out.rgb.at<cv::Vec3b>(cell.v, cell.u);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb[c], cell.rgb[c], 1) << cell.u << "," << cell.v;
    EXPECT_NEAR(out.depth.at<float>(cell.v, cell.u), 3.0f, kDepthTolerance);
  }
  EXPECT_TRUE(std::isnan(out.depth.at<float>(2, 2)));  // beyond the wall's edge
  EXPECT_EQ(cv::countNonZero(out.instance), 0);
  EXPECT_EQ(cv::countNonZero(out.amodal_bits), 0);
  EXPECT_TRUE(out.target_footprint.empty());
  renderer->render(lookAt(Eigen::Vector3d(-3, 0, 0), Eigen::Vector3d::Zero()), out);
  EXPECT_EQ(cv::countNonZero(out.depth == out.depth), 0);  // from behind: nothing (NaN)
}

}  // namespace
}  // namespace occlusion_env
