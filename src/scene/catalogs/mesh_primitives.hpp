// Procedural mesh primitives for the embedded catalogue (private to src/scene/catalogs).
// All sizes in metres, z up; each part gets one uniform vertex colour (linear RGB in [0, 1]).
// Triangles wind counter-clockwise seen from outside (the renderer does not cull anyway).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "occlusion_env/scene/mesh.hpp"

namespace occlusion_env {
namespace primitives {

using Color = Eigen::Vector3f;

/// Which ends of a cylinder or frustum are closed.
enum class Caps { kNone, kBottom, kTop, kBoth };

/// Axis-aligned box spanning [min, max].
Mesh box(const Eigen::Vector3f& min, const Eigen::Vector3f& max, const Color& color);

/// Axis-aligned box given its centre and edge lengths.
Mesh block(const Eigen::Vector3f& centre, const Eigen::Vector3f& size, const Color& color);

/// Surface of revolution about the z axis. `profile` holds (radius, z) points; walking along it,
/// the outside lies to the right (e.g. bottom centre -> bottom rim -> top rim -> top centre).
/// Points with radius 0 become single pole vertices; `segments` >= 3 around the axis.
Mesh lathe(const std::vector<Eigen::Vector2f>& profile, int segments, const Color& color);

/// Frustum (cone when a radius is 0) about z, from z = 0 to z = height.
Mesh frustum(float bottom_radius, float top_radius, float height, int segments, const Color& color,
             Caps caps = Caps::kBoth);

/// Cylinder about z, from z = 0 to z = height.
Mesh cylinder(float radius, float height, int segments, const Color& color,
              Caps caps = Caps::kBoth);

/// Closed cylinder of `radius` from point a to point b (legs, rods, arms).
Mesh rod(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float radius, int segments,
         const Color& color);

/// UV ellipsoid centred at the origin with semi-axes `radii`; `segments` around z, half as many
/// rings from pole to pole.
Mesh ellipsoid(const Eigen::Vector3f& radii, int segments, const Color& color);

/// UV sphere centred at the origin.
Mesh sphere(float radius, int segments, const Color& color);

/// Torus about the z axis in the xy plane, centred at the origin. The tube is swept from angle
/// `start` to `end` [rad] around z; a partial sweep (a handle) gets flat end caps.
Mesh torus(float major_radius, float minor_radius, int major_segments, int minor_segments,
           const Color& color, float start = 0.0f, float end = 6.28318531f);

}  // namespace primitives
}  // namespace occlusion_env
