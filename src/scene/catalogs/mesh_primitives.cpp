#include "mesh_primitives.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace primitives {
namespace {

constexpr float kTwoPi = 6.28318531f;

void addTriangle(Mesh& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  mesh.indices.insert(mesh.indices.end(), {a, b, c});
}

// Quad a-b-c-d, counter-clockwise seen from outside.
void addQuad(Mesh& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  addTriangle(mesh, a, b, c);
  addTriangle(mesh, a, c, d);
}

std::uint32_t addVertex(Mesh& mesh, const Eigen::Vector3f& position, const Color& color) {
  mesh.positions.push_back(position);
  mesh.colors.push_back(color);
  return static_cast<std::uint32_t>(mesh.positions.size() - 1);
}

void requireSegments(int segments, const char* what) {
  if (segments < 3) throw InvalidArgumentError(std::string(what) + ": need >= 3 segments");
}

}  // namespace

Mesh box(const Eigen::Vector3f& min, const Eigen::Vector3f& max, const Color& color) {
  Mesh mesh;
  // Corner i takes max along x, y, z where bit 0, 1, 2 of i is set.
  for (int i = 0; i < 8; ++i) {
    addVertex(mesh,
              {i & 1 ? max.x() : min.x(), i & 2 ? max.y() : min.y(), i & 4 ? max.z() : min.z()},
              color);
  }
  addQuad(mesh, 0, 2, 3, 1);  // -z
  addQuad(mesh, 4, 5, 7, 6);  // +z
  addQuad(mesh, 0, 1, 5, 4);  // -y
  addQuad(mesh, 2, 6, 7, 3);  // +y
  addQuad(mesh, 0, 4, 6, 2);  // -x
  addQuad(mesh, 1, 3, 7, 5);  // +x
  return mesh;
}

Mesh block(const Eigen::Vector3f& centre, const Eigen::Vector3f& size, const Color& color) {
  return box(centre - size / 2.0f, centre + size / 2.0f, color);
}

Mesh lathe(const std::vector<Eigen::Vector2f>& profile, int segments, const Color& color) {
  requireSegments(segments, "lathe");
  if (profile.size() < 2) throw InvalidArgumentError("lathe: profile needs >= 2 points");
  Mesh mesh;
  std::vector<std::uint32_t> ring_start;
  std::vector<bool> is_pole;
  for (const Eigen::Vector2f& point : profile) {
    const float radius = point.x(), z = point.y();
    ring_start.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
    is_pole.push_back(radius <= 1e-7f);
    if (is_pole.back()) {
      addVertex(mesh, {0.0f, 0.0f, z}, color);
      continue;
    }
    for (int j = 0; j < segments; ++j) {
      const float angle = kTwoPi * static_cast<float>(j) / static_cast<float>(segments);
      addVertex(mesh, {radius * std::cos(angle), radius * std::sin(angle), z}, color);
    }
  }
  auto vertex = [&](std::size_t ring, int j) {
    return is_pole[ring] ? ring_start[ring]
                         : ring_start[ring] + static_cast<std::uint32_t>(j % segments);
  };
  for (std::size_t i = 0; i + 1 < profile.size(); ++i) {
    if (is_pole[i] && is_pole[i + 1]) continue;
    for (int j = 0; j < segments; ++j) {
      const std::uint32_t a = vertex(i, j), b = vertex(i, j + 1), c = vertex(i + 1, j + 1),
                          d = vertex(i + 1, j);
      if (is_pole[i]) {
        addTriangle(mesh, a, c, d);
      } else if (is_pole[i + 1]) {
        addTriangle(mesh, a, b, c);
      } else {
        addQuad(mesh, a, b, c, d);
      }
    }
  }
  return mesh;
}

Mesh frustum(float bottom_radius, float top_radius, float height, int segments, const Color& color,
             Caps caps) {
  std::vector<Eigen::Vector2f> profile;
  if (caps == Caps::kBottom || caps == Caps::kBoth) profile.emplace_back(0.0f, 0.0f);
  profile.emplace_back(bottom_radius, 0.0f);
  profile.emplace_back(top_radius, height);
  if (caps == Caps::kTop || caps == Caps::kBoth) profile.emplace_back(0.0f, height);
  return lathe(profile, segments, color);
}

Mesh cylinder(float radius, float height, int segments, const Color& color, Caps caps) {
  return frustum(radius, radius, height, segments, color, caps);
}

Mesh rod(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float radius, int segments,
         const Color& color) {
  const Eigen::Vector3f axis = b - a;
  const float length = axis.norm();
  if (!(length > 0.0f)) throw InvalidArgumentError("rod: end points coincide");
  // Orthonormal frame whose z column is the rod axis.
  const Eigen::Vector3f z = axis / length;
  const Eigen::Vector3f helper =
      std::abs(z.z()) < 0.9f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitX();
  const Eigen::Vector3f x = helper.cross(z).normalized();
  Eigen::Affine3f placement = Eigen::Affine3f::Identity();
  placement.linear() << x, z.cross(x), z;
  placement.translation() = a;
  Mesh mesh;
  appendMesh(mesh, cylinder(radius, length, segments, color), placement);
  return mesh;
}

Mesh ellipsoid(const Eigen::Vector3f& radii, int segments, const Color& color) {
  requireSegments(segments, "ellipsoid");
  const int rings = std::max(2, segments / 2);
  std::vector<Eigen::Vector2f> profile;  // unit semicircle from the south to the north pole
  for (int k = 0; k <= rings; ++k) {
    const float latitude = -kTwoPi / 4.0f + kTwoPi / 2.0f * static_cast<float>(k) / rings;
    const bool pole = k == 0 || k == rings;
    profile.emplace_back(pole ? 0.0f : std::cos(latitude),
                         pole ? (k == 0 ? -1.0f : 1.0f) : std::sin(latitude));
  }
  Mesh mesh = lathe(profile, segments, color);
  for (auto& p : mesh.positions) p = p.cwiseProduct(radii);
  return mesh;
}

Mesh sphere(float radius, int segments, const Color& color) {
  return ellipsoid(Eigen::Vector3f::Constant(radius), segments, color);
}

Mesh torus(float major_radius, float minor_radius, int major_segments, int minor_segments,
           const Color& color, float start, float end) {
  requireSegments(major_segments, "torus");
  requireSegments(minor_segments, "torus");
  const bool closed = std::abs(end - start) >= kTwoPi - 1e-5f;
  const int rings = closed ? major_segments : major_segments + 1;  // tube cross-sections
  Mesh mesh;
  for (int i = 0; i < rings; ++i) {
    const float theta = start + (end - start) * static_cast<float>(i) / major_segments;
    for (int j = 0; j < minor_segments; ++j) {
      const float phi = kTwoPi * static_cast<float>(j) / minor_segments;
      const float radius = major_radius + minor_radius * std::cos(phi);
      addVertex(mesh,
                {radius * std::cos(theta), radius * std::sin(theta), minor_radius * std::sin(phi)},
                color);
    }
  }
  auto vertex = [&](int i, int j) {
    return static_cast<std::uint32_t>((i % rings) * minor_segments + j % minor_segments);
  };
  for (int i = 0; i < major_segments; ++i) {
    for (int j = 0; j < minor_segments; ++j) {
      addQuad(mesh, vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1));
    }
  }
  if (!closed) {  // flat caps over both open ends
    for (int end_ring : {0, rings - 1}) {
      const float theta = end_ring == 0 ? start : end;
      const std::uint32_t centre = addVertex(
          mesh, {major_radius * std::cos(theta), major_radius * std::sin(theta), 0.0f}, color);
      for (int j = 0; j < minor_segments; ++j) {
        if (end_ring == 0) {
          addTriangle(mesh, centre, vertex(end_ring, j), vertex(end_ring, j + 1));
        } else {
          addTriangle(mesh, centre, vertex(end_ring, j + 1), vertex(end_ring, j));
        }
      }
    }
  }
  return mesh;
}

}  // namespace primitives
}  // namespace occlusion_env
