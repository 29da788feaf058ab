// The embedded catalogue: enough distinct, well-formed objects with real structure (hollows,
// space between legs) at plausible real-world sizes.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/scene/mesh.hpp"
#include "occlusion_env/scene/object_catalog.hpp"

namespace occlusion_env {
namespace {

// Ray parameters t > 0 at which origin + t * dir crosses any triangle (Moeller-Trumbore).
std::vector<float> rayHits(const Mesh& mesh, const Eigen::Vector3f& origin,
                           const Eigen::Vector3f& dir) {
  std::vector<float> hits;
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const Eigen::Vector3f& v0 = mesh.positions[mesh.indices[i]];
    const Eigen::Vector3f e1 = mesh.positions[mesh.indices[i + 1]] - v0;
    const Eigen::Vector3f e2 = mesh.positions[mesh.indices[i + 2]] - v0;
    const Eigen::Vector3f p = dir.cross(e2);
    const float det = e1.dot(p);
    if (std::abs(det) < 1e-12f) continue;  // parallel (or degenerate triangle)
    const Eigen::Vector3f s = origin - v0;
    const float u = s.dot(p) / det;
    if (u < 0.0f || u > 1.0f) continue;
    const Eigen::Vector3f q = s.cross(e1);
    const float v = dir.dot(q) / det;
    if (v < 0.0f || u + v > 1.0f) continue;
    const float t = e2.dot(q) / det;
    if (t > 0.0f) hits.push_back(t);
  }
  std::sort(hits.begin(), hits.end());
  return hits;
}

std::string firstIdOf(const ObjectCatalog& catalog, const std::string& category) {
  for (const ObjectInfo& info : catalog.objects())
    if (info.category == category) return info.id;
  return "";
}

TEST(EmbeddedCatalog, HasEnoughObjectsAndCategories) {
  const auto catalog = makeEmbeddedCatalog();
  EXPECT_EQ(catalog->sourceName(), "embedded");
  const auto& objects = catalog->objects();
  EXPECT_GE(objects.size(), 10u);
  std::set<std::string> categories;
  for (const ObjectInfo& info : objects) categories.insert(info.category);
  EXPECT_GE(categories.size(), 5u);
  for (const char* required : {"chair", "table", "lamp", "mug"})
    EXPECT_EQ(categories.count(required), 1u) << required;
}

TEST(EmbeddedCatalog, IdsAreUniqueSortedAndInfoComplete) {
  const auto catalog = makeEmbeddedCatalog();
  const auto& objects = catalog->objects();
  for (std::size_t i = 1; i < objects.size(); ++i)
    EXPECT_LT(objects[i - 1].id, objects[i].id);  // strictly increasing: sorted and unique
  for (const ObjectInfo& info : objects) {
    EXPECT_EQ(info.id.rfind("embedded/", 0), 0u) << info.id;
    EXPECT_FALSE(info.name.empty()) << info.id;
    EXPECT_EQ(info.source_category, "embedded");
    EXPECT_EQ(info.creator, "occlusion_env");
    EXPECT_EQ(info.license, "BSD-3-Clause");
    std::string lower = info.category;
    std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
    EXPECT_EQ(info.category, lower);
  }
}

TEST(EmbeddedCatalog, MeshesAreValidAndRealSized) {
  const auto catalog = makeEmbeddedCatalog();
  for (const ObjectInfo& info : catalog->objects()) {
    SCOPED_TRACE(info.id);
    const Mesh mesh = catalog->loadMesh(info.id);
    EXPECT_NO_THROW(validateMesh(mesh, info.id));
    EXPECT_GT(mesh.triangleCount(), 100u);
    EXPECT_LE(mesh.triangleCount(), 5000u);
    for (const Eigen::Vector3f& c : mesh.colors)
      ASSERT_TRUE((c.array() >= 0.0f).all() && (c.array() <= 1.0f).all());
    const Eigen::AlignedBox3f box = boundingBox(mesh);
    const Eigen::Vector3f size = box.sizes();
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_GE(size[axis], 0.05f) << "axis " << axis;
      EXPECT_LE(size[axis], 2.5f) << "axis " << axis;
    }
    EXPECT_NEAR(box.min().z(), 0.0f, 1e-3f);  // resting on the floor
    // width (y), depth (x), height (z)
    EXPECT_NEAR(info.dimensions_m.x(), size.y(), 1e-5f);
    EXPECT_NEAR(info.dimensions_m.y(), size.x(), 1e-5f);
    EXPECT_NEAR(info.dimensions_m.z(), size.z(), 1e-5f);
  }
}

TEST(EmbeddedCatalog, UnknownIdThrowsNamingIt) {
  const auto catalog = makeEmbeddedCatalog();
  try {
    catalog->loadMesh("embedded/no_such_thing");
    FAIL() << "expected InvalidArgumentError";
  } catch (const InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("embedded/no_such_thing"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find(catalog->objects().front().id), std::string::npos);
  }
}

TEST(EmbeddedCatalog, MugIsHollow) {
  const auto catalog = makeEmbeddedCatalog();
  const std::string id = firstIdOf(*catalog, "mug");
  ASSERT_FALSE(id.empty());
  const Mesh mesh = catalog->loadMesh(id);
  const Eigen::AlignedBox3f box = boundingBox(mesh);
  // The body is round and symmetric in x; the handle sticks out towards +y.
  const float radius = box.sizes().x() / 2;
  const Eigen::Vector3f above(box.center().x() + 0.003f, box.min().y() + radius + 0.002f,
                              box.max().z() + 0.1f);  // just off the axis, avoiding fan centres
  const auto hits = rayHits(mesh, above, -Eigen::Vector3f::UnitZ());
  ASSERT_GE(hits.size(), 2u);  // inner bottom, outer bottom
  const float first_z = above.z() - hits.front();
  EXPECT_LT(first_z, box.min().z() + 0.2f * box.sizes().z());  // the bottom, not a lid
  EXPECT_GT(first_z, box.min().z());                           // inside, above the outer base
}

TEST(EmbeddedCatalog, ChairHasSpaceUnderItsSeat) {
  const auto catalog = makeEmbeddedCatalog();
  const Mesh mesh = catalog->loadMesh("embedded/chair_slat");
  const Eigen::AlignedBox3f box = boundingBox(mesh);
  const float z = box.min().z() + 0.28f * box.sizes().z();  // below the seat, above stretchers
  const Eigen::Vector3f centre = box.center();
  // Side to side and front to back through the middle, between the legs.
  EXPECT_TRUE(
      rayHits(mesh, {centre.x(), box.min().y() - 0.1f, z}, Eigen::Vector3f::UnitY()).empty());
  EXPECT_TRUE(
      rayHits(mesh, {box.max().x() + 0.1f, centre.y(), z}, -Eigen::Vector3f::UnitX()).empty());
  // The same ray at seat height does hit the chair.
  const float seat_z = box.min().z() + 0.5f * box.sizes().z();
  EXPECT_FALSE(
      rayHits(mesh, {centre.x(), box.min().y() - 0.1f, seat_z}, Eigen::Vector3f::UnitY()).empty());
}

TEST(EmbeddedCatalog, BuildsAreDeterministic) {
  const auto first = makeEmbeddedCatalog();
  const auto second = makeEmbeddedCatalog();
  ASSERT_EQ(first->objects().size(), second->objects().size());
  for (const ObjectInfo& info : first->objects()) {
    SCOPED_TRACE(info.id);
    const Mesh a = first->loadMesh(info.id), b = second->loadMesh(info.id);
    EXPECT_EQ(a.indices, b.indices);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.colors, b.colors);
    const Mesh again = first->loadMesh(info.id);
    EXPECT_EQ(a.positions, again.positions);
  }
}

}  // namespace
}  // namespace occlusion_env
