// The project's own objects, built procedurally from primitives: no data files, no third-party
// models. Metres at real-world scale, z up, front facing +x, resting on z = 0.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mesh_primitives.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/scene/object_catalog.hpp"

namespace occlusion_env {
namespace {

using Eigen::Affine3f;
using Eigen::Vector2f;
using Eigen::Vector3f;
using primitives::block;
using primitives::Caps;
using primitives::Color;

constexpr float kPi = 3.14159265f;

// Palette (linear RGB), saturated enough that parts stay distinct in a segmentation-free render.
const Color kOak(0.45f, 0.22f, 0.07f);
const Color kWalnut(0.16f, 0.06f, 0.02f);
const Color kBlackMetal(0.03f, 0.03f, 0.035f);
const Color kChrome(0.55f, 0.56f, 0.6f);
const Color kBrass(0.6f, 0.38f, 0.08f);
const Color kRedFabric(0.55f, 0.03f, 0.03f);
const Color kBlueFabric(0.04f, 0.09f, 0.4f);
const Color kLightBlueFabric(0.12f, 0.25f, 0.65f);
const Color kGreenVelvet(0.04f, 0.28f, 0.08f);
const Color kMustard(0.62f, 0.4f, 0.02f);
const Color kTeal(0.02f, 0.3f, 0.3f);
const Color kLaminate(0.75f, 0.74f, 0.7f);
const Color kLampRed(0.65f, 0.04f, 0.02f);
const Color kShadeYellow(0.85f, 0.62f, 0.15f);
const Color kBulb(0.95f, 0.9f, 0.65f);
const Color kGlazeOrange(0.8f, 0.18f, 0.02f);
const Color kBottleGreen(0.02f, 0.22f, 0.05f);
const Color kLabelCream(0.8f, 0.7f, 0.45f);
const Color kFoilRed(0.5f, 0.02f, 0.05f);
const Color kCobalt(0.03f, 0.12f, 0.6f);
const Color kTerracotta(0.55f, 0.16f, 0.05f);
const Color kSoil(0.07f, 0.035f, 0.01f);
const Color kLeafGreen(0.06f, 0.4f, 0.05f);
const Color kStemGreen(0.03f, 0.18f, 0.02f);

Affine3f at(float x, float y, float z) {
  return Affine3f(Eigen::Translation3f(x, y, z));
}
Affine3f turn(float angle, const Vector3f& axis) {
  return Affine3f(Eigen::AngleAxisf(angle, axis.normalized()));
}
Affine3f yaw(float angle) {
  return turn(angle, Vector3f::UnitZ());
}

// Rotates about the y axis through `pivot`; positive angles tip +z towards -x.
Affine3f tiltAbout(const Vector3f& pivot, float angle) {
  return Eigen::Translation3f(pivot) * turn(angle, Vector3f::UnitY()) *
         Eigen::Translation3f(-pivot);
}

// Dining chair: four legs, aprons, side stretchers, seat board with cushion, slatted back.
// 0.48 deep x 0.41 wide x 0.90 high; open space under the seat between the legs.
Mesh slatBackChair() {
  Mesh m;
  const float leg = 0.035f, lx = 0.205f, ly = 0.1875f;  // leg section; leg centres at +-lx, +-ly
  for (float sy : {-1.0f, 1.0f}) {
    appendMesh(m, block({lx, sy * ly, 0.215f}, {leg, leg, 0.43f}, kOak));      // front leg
    appendMesh(m, block({-lx, sy * ly, 0.45f}, {leg, leg, 0.90f}, kOak));      // rear leg + post
    appendMesh(m, block({0, sy * ly, 0.395f}, {2 * lx, 0.02f, 0.07f}, kOak));  // side apron
    appendMesh(m, block({0, sy * ly, 0.13f}, {2 * lx, 0.02f, 0.025f}, kOak));  // stretcher
  }
  for (float sx : {-1.0f, 1.0f}) {
    appendMesh(m, block({sx * lx, 0, 0.395f}, {0.02f, 2 * ly, 0.07f}, kOak));  // front/back apron
  }
  appendMesh(m, block({0, 0, 0.445f}, {0.48f, 0.44f, 0.03f}, kOak));           // seat board
  appendMesh(m, block({0.02f, 0, 0.48f}, {0.40f, 0.38f, 0.04f}, kRedFabric));  // cushion
  appendMesh(m, block({-lx, 0, 0.84f}, {0.025f, 2 * ly, 0.08f}, kOak));        // top rail
  appendMesh(m, block({-lx, 0, 0.565f}, {0.025f, 2 * ly, 0.03f}, kOak));       // low rail
  for (float y : {-0.09f, 0.0f, 0.09f}) {
    appendMesh(m, block({-lx, y, 0.69f}, {0.015f, 0.04f, 0.22f}, kWalnut));  // back slats
  }
  return m;
}

// Swivel office chair: five-spoke base on casters, gas lift, seat, tilted backrest, armrests.
Mesh officeChair() {
  Mesh m;
  const float caster = 0.025f;  // caster radius [m]
  for (int i = 0; i < 5; ++i) {
    const Affine3f spoke = yaw(2 * kPi * i / 5);
    appendMesh(m, block({0.15f, 0, 0.075f}, {0.30f, 0.04f, 0.03f}, kBlackMetal), spoke);
    appendMesh(m, primitives::sphere(caster, 16, kBlackMetal), spoke * at(0.28f, 0, caster));
    appendMesh(m, primitives::rod({0.28f, 0, caster}, {0.28f, 0, 0.075f}, 0.007f, 8, kChrome),
               spoke);
  }
  appendMesh(m, primitives::cylinder(0.04f, 0.05f, 24, kBlackMetal), at(0, 0, 0.06f));  // hub
  appendMesh(m, primitives::cylinder(0.022f, 0.32f, 24, kChrome), at(0, 0, 0.10f));     // gas lift
  appendMesh(m, block({0, 0, 0.41f}, {0.25f, 0.25f, 0.02f}, kBlackMetal));         // seat plate
  appendMesh(m, block({0.02f, 0, 0.46f}, {0.48f, 0.48f, 0.08f}, kBlueFabric));     // seat
  appendMesh(m, block({-0.15f, 0, 0.41f}, {0.22f, 0.05f, 0.015f}, kBlackMetal));   // back arm
  appendMesh(m, block({-0.255f, 0, 0.52f}, {0.015f, 0.05f, 0.24f}, kBlackMetal));  // back arm
  appendMesh(m, block({-0.28f, 0, 0.82f}, {0.06f, 0.44f, 0.44f}, kBlueFabric),
             tiltAbout({-0.26f, 0, 0.6f}, -0.15f));  // backrest, reclined 9 degrees
  for (float sy : {-1.0f, 1.0f}) {
    appendMesh(m, block({0, sy * 0.235f, 0.435f}, {0.05f, 0.07f, 0.015f}, kBlackMetal));
    appendMesh(m, block({0, sy * 0.27f, 0.55f}, {0.04f, 0.015f, 0.24f}, kBlackMetal));
    appendMesh(m, block({0.02f, sy * 0.27f, 0.68f}, {0.26f, 0.06f, 0.025f}, kBlackMetal));
  }
  return m;
}

// Bar stool: round cushioned seat on four splayed metal legs with a footrest ring.
Mesh barStool() {
  Mesh m;
  const float seat_z = 0.72f, top_r = 0.12f, foot_r = 0.20f, ring_z = 0.28f;
  const float leg_z = seat_z + 0.015f;  // legs end inside the seat disc
  for (int i = 0; i < 4; ++i) {
    const float a = kPi / 4 + kPi / 2 * i;
    const Vector3f dir(std::cos(a), std::sin(a), 0);
    appendMesh(m, primitives::rod(foot_r * dir, top_r * dir + Vector3f(0, 0, leg_z), 0.014f, 12,
                                  kBlackMetal));
  }
  const float ring_r = foot_r - (foot_r - top_r) * ring_z / leg_z;  // legs' radius at ring_z
  appendMesh(m, primitives::torus(ring_r, 0.01f, 48, 10, kChrome), at(0, 0, ring_z));
  appendMesh(m, primitives::cylinder(0.19f, 0.035f, 40, kWalnut), at(0, 0, seat_z));
  appendMesh(m, primitives::frustum(0.18f, 0.16f, 0.04f, 40, kMustard), at(0, 0, seat_z + 0.035f));
  return m;
}

// Rectangular dining table: top on four turned legs joined by aprons.
Mesh diningTable() {
  Mesh m;
  const float lx = 0.36f, ly = 0.68f, top_z = 0.715f;  // leg centres; underside of the top
  const std::vector<Vector2f> turned_leg = {
      {0, 0},          {0.022f, 0},    {0.027f, 0.03f}, {0.02f, 0.06f}, {0.024f, 0.25f},
      {0.031f, 0.45f}, {0.02f, 0.55f}, {0.03f, 0.58f},  {0.03f, top_z}, {0, top_z}};
  const Mesh leg = primitives::lathe(turned_leg, 12, kOak);
  for (float sx : {-1.0f, 1.0f}) {
    for (float sy : {-1.0f, 1.0f}) appendMesh(m, leg, at(sx * lx, sy * ly, 0));
    appendMesh(m, block({sx * lx, 0, 0.665f}, {0.022f, 2 * ly, 0.1f}, kOak));  // end apron
    appendMesh(m, block({0, sx * ly, 0.665f}, {2 * lx, 0.022f, 0.1f}, kOak));  // long apron
  }
  appendMesh(m, block({0, 0, top_z + 0.0175f}, {0.85f, 1.5f, 0.035f}, kWalnut));
  return m;
}

// Round pedestal table: disc top on a turned column standing on four feet.
Mesh roundTable() {
  Mesh m;
  appendMesh(m, primitives::cylinder(0.45f, 0.03f, 48, kWalnut), at(0, 0, 0.72f));
  const std::vector<Vector2f> column = {{0, 0.05f},      {0.07f, 0.05f}, {0.045f, 0.1f},
                                        {0.035f, 0.58f}, {0.05f, 0.66f}, {0.11f, 0.72f},
                                        {0.11f, 0.73f},  {0, 0.73f}};  // top end inside the disc
  appendMesh(m, primitives::lathe(column, 24, kBlackMetal));
  for (int i = 0; i < 4; ++i) {
    const Affine3f foot = yaw(kPi / 4 + kPi / 2 * i);
    appendMesh(m, block({0.17f, 0, 0.035f}, {0.34f, 0.05f, 0.04f}, kBlackMetal), foot);
    appendMesh(m, block({0.31f, 0, 0.0075f}, {0.06f, 0.06f, 0.015f}, kChrome), foot);  // pad
  }
  return m;
}

// Office desk: laminate top, side panel, three-drawer pedestal, modesty panel; open knee space.
Mesh desk() {
  Mesh m;
  appendMesh(m, block({0, 0, 0.735f}, {0.65f, 1.3f, 0.03f}, kLaminate));       // top
  appendMesh(m, block({0, -0.62f, 0.36f}, {0.6f, 0.03f, 0.72f}, kTeal));       // side panel
  appendMesh(m, block({-0.01f, 0.43f, 0.36f}, {0.58f, 0.42f, 0.72f}, kTeal));  // pedestal
  appendMesh(m, block({-0.27f, -0.2f, 0.5f}, {0.02f, 0.84f, 0.4f}, kTeal));    // modesty panel
  for (float z : {0.13f, 0.365f, 0.6f}) {
    appendMesh(m, block({0.29f, 0.43f, z}, {0.02f, 0.40f, 0.22f}, kLaminate));  // drawer front
    for (float y : {0.37f, 0.49f}) {
      appendMesh(m, block({0.305f, y, z + 0.07f}, {0.012f, 0.01f, 0.01f}, kChrome));
    }
    appendMesh(m, primitives::rod({0.312f, 0.36f, z + 0.07f}, {0.312f, 0.50f, z + 0.07f}, 0.006f, 8,
                                  kChrome));  // handle bar
  }
  return m;
}

// Articulated desk lamp: disc base, twin-rod arms, conical shade tipped forward over a bulb.
Mesh deskLamp() {
  Mesh m;
  appendMesh(m, primitives::cylinder(0.075f, 0.025f, 32, kLampRed));
  const Vector3f base(-0.02f, 0, 0.02f), elbow(-0.07f, 0, 0.30f), head(0.17f, 0, 0.36f);
  for (float sy : {-0.012f, 0.012f}) {
    const Vector3f side(0, sy, 0);
    appendMesh(m, primitives::rod(base + side, elbow + side, 0.006f, 8, kChrome));
    appendMesh(m, primitives::rod(elbow + side, head + side, 0.006f, 8, kChrome));
  }
  appendMesh(m, primitives::sphere(0.016f, 16, kBlackMetal), at(elbow.x(), 0, elbow.z()));
  appendMesh(m, primitives::sphere(0.016f, 16, kBlackMetal), at(head.x(), 0, head.z()));
  // Shade: narrow closed end at the head, open mouth pointing down and forward.
  const float shade_h = 0.12f;
  const Affine3f shade =
      at(head.x(), head.y(), head.z()) * turn(-0.55f, Vector3f::UnitY()) * at(0, 0, -shade_h);
  appendMesh(m, primitives::frustum(0.075f, 0.022f, shade_h, 32, kLampRed, Caps::kTop), shade);
  appendMesh(m, primitives::sphere(0.025f, 16, kBulb), shade * at(0, 0, 0.05f));
  return m;
}

// Floor lamp: weighted base, brass stem, open drum shade around a bulb.
Mesh floorLamp() {
  Mesh m;
  appendMesh(m, primitives::frustum(0.17f, 0.15f, 0.03f, 40, kBlackMetal));
  appendMesh(m, primitives::cylinder(0.012f, 1.42f, 16, kBrass), at(0, 0, 0.03f));
  appendMesh(m, primitives::cylinder(0.02f, 0.04f, 16, kBrass), at(0, 0, 1.43f));  // socket
  appendMesh(m, primitives::sphere(0.04f, 20, kBulb), at(0, 0, 1.50f));
  appendMesh(m, primitives::frustum(0.23f, 0.17f, 0.30f, 40, kShadeYellow, Caps::kNone),
             at(0, 0, 1.30f));
  for (int i = 0; i < 3; ++i) {  // spokes from the socket to the shade's top rim
    const float a = 2 * kPi * i / 3;
    appendMesh(m, primitives::rod({0, 0, 1.46f}, {0.17f * std::cos(a), 0.17f * std::sin(a), 1.6f},
                                  0.004f, 6, kBrass));
  }
  return m;
}

// Mug: one lathe for bottom, outer wall, rim and inner wall (hollow, open top); torus-arc handle
// on the +y side whose capped ends sit in the wall.
Mesh mug() {
  Mesh m;
  const float r = 0.042f, h = 0.095f, wall = 0.004f, bottom = 0.006f;
  appendMesh(m, primitives::lathe({{0, 0},
                                   {r - 0.003f, 0},
                                   {r, 0.003f},
                                   {r, h},
                                   {r - wall, h},
                                   {r - wall, bottom},
                                   {0, bottom}},
                                  40, kGlazeOrange));
  const float handle_r = 0.025f, offset = 0.006f;  // handle arc radius; its centre outside the wall
  const float end = std::asin((offset - 0.002f) / handle_r);  // ends 2 mm outside the wall
  appendMesh(m, primitives::torus(handle_r, 0.0055f, 24, 10, kGlazeOrange, -end, kPi + end),
             at(0, r + offset, h / 2) * turn(kPi / 2, Vector3f::UnitY()));
  return m;
}

// Wine bottle: lathe profile with a punt, shoulder and neck; paper label and foil capsule.
Mesh wineBottle() {
  Mesh m;
  appendMesh(m, primitives::lathe({{0, 0.02f},
                                   {0.02f, 0.01f},
                                   {0.032f, 0},
                                   {0.037f, 0.004f},
                                   {0.037f, 0.2f},
                                   {0.032f, 0.232f},
                                   {0.017f, 0.258f},
                                   {0.0135f, 0.275f},
                                   {0.0135f, 0.3f},
                                   {0.0155f, 0.302f},
                                   {0.0155f, 0.31f},
                                   {0, 0.31f}},
                                  32, kBottleGreen));
  appendMesh(m, primitives::cylinder(0.0385f, 0.09f, 32, kLabelCream, Caps::kNone),
             at(0, 0, 0.06f));
  appendMesh(m, primitives::cylinder(0.0145f, 0.038f, 32, kFoilRed, Caps::kTop), at(0, 0, 0.274f));
  return m;
}

// Vase: bulbous lathe with a flared, open mouth and an inner wall 5 mm inside the outer one.
Mesh vase() {
  const std::vector<Vector2f> outer = {
      // (radius, z) [m], foot to flared lip
      {0.048f, 0},     {0.058f, 0.02f},  {0.07f, 0.05f}, {0.08f, 0.08f},  {0.085f, 0.11f},
      {0.083f, 0.14f}, {0.075f, 0.17f},  {0.062f, 0.2f}, {0.048f, 0.23f}, {0.04f, 0.26f},
      {0.039f, 0.28f}, {0.042f, 0.295f}, {0.048f, 0.31f}};
  std::vector<Vector2f> profile = {{0, 0}};
  profile.insert(profile.end(), outer.begin(), outer.end());
  for (auto it = outer.rbegin(); it != outer.rend() - 2; ++it) {
    profile.emplace_back(it->x() - 0.005f, it->y());  // inner wall, walking down
  }
  profile.emplace_back(0.05f, 0.012f);
  profile.emplace_back(0, 0.012f);
  return primitives::lathe(profile, 40, kCobalt);
}

// Bookshelf without a back panel (you can see through it), with rows of books of varied size.
Mesh bookshelf() {
  Mesh m;
  const float depth = 0.3f, width = 0.8f, height = 1.8f, t = 0.02f;
  for (float sy : {-1.0f, 1.0f}) {
    appendMesh(m, block({0, sy * (width - t) / 2, height / 2}, {depth, t, height}, kWalnut));
  }
  appendMesh(m, block({0, 0, height - t / 2}, {depth, width, t}, kWalnut));            // top
  appendMesh(m, block({depth / 2 - 0.01f, 0, 0.05f}, {0.02f, width, 0.1f}, kWalnut));  // plinth
  const std::vector<Color> covers = {kRedFabric, kCobalt,     kMustard, kGreenVelvet,
                                     kTeal,      kLabelCream, kLampRed, kLightBlueFabric};
  std::uint32_t state = 20240601u;  // fixed seed: the same books every time
  auto uniform = [&state](float lo, float hi) {
    state = state * 1664525u + 1013904223u;  // LCG, identical on every platform
    return lo + (hi - lo) * static_cast<float>(state >> 8) / 16777216.0f;
  };
  const float fill[] = {0.9f, 0.55f, 0.75f, 0.35f};  // share of each shelf taken by books
  for (int shelf = 0; shelf < 4; ++shelf) {
    const float z = 0.1f + 0.42f * shelf;  // shelf underside [m]
    appendMesh(m, block({0, 0, z + t / 2}, {depth, width - 2 * t, t}, kWalnut));
    float y = -width / 2 + t + 0.01f;
    const float y_end = y + fill[shelf] * (width - 2 * t - 0.02f);
    while (true) {
      const float thick = uniform(0.02f, 0.05f), tall = uniform(0.18f, 0.3f);
      const float deep = uniform(0.15f, 0.22f);
      if (y + thick > y_end) break;
      const Color& cover = covers[static_cast<std::size_t>(uniform(0, 7.999f))];
      appendMesh(m, block({-depth / 2 + 0.01f + deep / 2, y + thick / 2, z + t + tall / 2},
                          {deep, thick, tall}, cover));
      y += thick + (uniform(0, 1) < 0.15f ? 0.03f : 0.002f);  // an occasional gap
    }
  }
  return m;
}

// Upholstered seat (sofa or armchair): legs, base, rounded arms, back, seat and back cushions.
Mesh upholstered(int seats, float width, const Color& fabric, const Color& cushion) {
  Mesh m;
  const float depth = 0.9f, arm = 0.16f, back = 0.2f, half = width / 2;
  for (float sx : {-1.0f, 1.0f}) {
    for (float sy : {-1.0f, 1.0f}) {
      appendMesh(m, primitives::frustum(0.022f, 0.03f, 0.1f, 12, kWalnut),
                 at(sx * (depth / 2 - 0.07f), sy * (half - 0.07f), 0));
    }
  }
  appendMesh(m, block({0, 0, 0.25f}, {depth, width, 0.3f}, fabric));                       // base
  appendMesh(m, block({-depth / 2 + back / 2, 0, 0.625f}, {back, width, 0.45f}, fabric));  // back
  for (float sy : {-1.0f, 1.0f}) {
    const float y = sy * (half - arm / 2);
    appendMesh(m, block({0, y, 0.51f}, {depth, arm, 0.22f}, fabric));
    appendMesh(m,
               primitives::rod({-depth / 2, y, 0.62f}, {depth / 2, y, 0.62f}, arm / 2, 16, fabric));
  }
  const float inner = width - 2 * arm, cushion_w = inner / seats - 0.01f;
  for (int i = 0; i < seats; ++i) {
    const float y = -inner / 2 + inner * (i + 0.5f) / seats;
    appendMesh(m, block({back / 2, y, 0.465f}, {depth - back - 0.01f, cushion_w, 0.13f}, cushion));
    const Vector3f back_cushion(-depth / 2 + back + 0.07f, y, 0.69f);
    appendMesh(m, block(back_cushion, {0.14f, cushion_w, 0.32f}, cushion),
               tiltAbout(back_cushion, -0.15f));
  }
  return m;
}

Mesh sofa() {
  return upholstered(3, 2.0f, kBlueFabric, kLightBlueFabric);
}
Mesh armchair() {
  return upholstered(1, 0.95f, kGreenVelvet, kMustard);
}

// Potted plant: hollow terracotta pot with soil, stems fanning out to flat ellipsoid leaves.
Mesh pottedPlant() {
  Mesh m;
  appendMesh(m, primitives::lathe({{0, 0},
                                   {0.07f, 0},
                                   {0.095f, 0.16f},
                                   {0.105f, 0.165f},
                                   {0.105f, 0.19f},
                                   {0.095f, 0.19f},
                                   {0.088f, 0.17f},
                                   {0, 0.17f}},
                                  32, kTerracotta));
  appendMesh(m, primitives::cylinder(0.089f, 0.004f, 32, kSoil, Caps::kTop), at(0, 0, 0.168f));
  const Mesh leaf = primitives::ellipsoid({0.12f, 0.04f, 0.006f}, 16, kLeafGreen);
  for (int i = 0; i < 8; ++i) {
    const float heading = 2 * kPi * i / 8 + 0.3f * (i % 2);
    const float stem_h = 0.3f + 0.08f * (i % 3), pitch = 0.55f - 0.2f * (i % 3);  // [m], [rad]
    const Vector3f tip(0.04f * std::cos(heading), 0.04f * std::sin(heading), stem_h);
    appendMesh(m, primitives::rod({0, 0, 0.17f}, tip, 0.004f, 6, kStemGreen));
    appendMesh(m, leaf,
               Eigen::Translation3f(tip) * yaw(heading) * turn(-pitch, Vector3f::UnitY()) *
                   at(0.11f, 0, 0));  // leaf base at the stem tip, rising at `pitch`
  }
  return m;
}

struct Recipe {
  const char* id;  // without the "embedded/" prefix
  const char* name;
  const char* category;
  Mesh (*build)();
};

const Recipe kRecipes[] = {
    {"armchair_club", "Club armchair", "armchair", armchair},
    {"bookshelf_open", "Open bookshelf with books", "shelf", bookshelf},
    {"bottle_wine", "Wine bottle", "bottle", wineBottle},
    {"chair_office", "Swivel office chair", "chair", officeChair},
    {"chair_slat", "Slat-back dining chair", "chair", slatBackChair},
    {"desk_pedestal", "Pedestal desk", "desk", desk},
    {"lamp_desk", "Articulated desk lamp", "lamp", deskLamp},
    {"lamp_floor", "Drum-shade floor lamp", "lamp", floorLamp},
    {"mug", "Coffee mug", "mug", mug},
    {"plant_potted", "Potted plant", "plant", pottedPlant},
    {"sofa_three_seat", "Three-seat sofa", "sofa", sofa},
    {"stool_bar", "Bar stool", "stool", barStool},
    {"table_dining", "Dining table", "table", diningTable},
    {"table_round", "Round pedestal table", "table", roundTable},
    {"vase", "Vase", "vase", vase},
};

class EmbeddedCatalog final : public ObjectCatalog {
 public:
  // Meshes are a few thousand triangles in all, so all are built up front.
  EmbeddedCatalog() {
    for (const Recipe& recipe : kRecipes) {
      Mesh mesh = recipe.build();
      const float floor_z = boundingBox(mesh).min().z();
      for (auto& p : mesh.positions) p.z() -= floor_z;  // rest on z = 0
      const Vector3f size = boundingBox(mesh).sizes();
      ObjectInfo info;
      info.id = std::string("embedded/") + recipe.id;
      info.name = recipe.name;
      info.category = recipe.category;
      info.source_category = "embedded";
      info.creator = "occlusion_env";
      info.license = "BSD-3-Clause";
      info.dimensions_m = Vector3f(size.y(), size.x(), size.z());  // width, depth, height
      meshes_.emplace(info.id, std::move(mesh));
      objects_.push_back(std::move(info));
    }
    std::sort(objects_.begin(), objects_.end(),
              [](const ObjectInfo& a, const ObjectInfo& b) { return a.id < b.id; });
  }

  std::string sourceName() const override { return "embedded"; }

  const std::vector<ObjectInfo>& objects() const override { return objects_; }

  Mesh loadMesh(const std::string& id) const override {
    const auto it = meshes_.find(id);
    if (it == meshes_.end()) {
      std::string valid;
      for (const ObjectInfo& info : objects_) valid += (valid.empty() ? "" : ", ") + info.id;
      throw InvalidArgumentError("embedded catalogue: unknown object id " + quoted(id) +
                                 "; valid ids: " + valid);
    }
    return it->second;
  }

 private:
  std::vector<ObjectInfo> objects_;
  std::map<std::string, Mesh> meshes_;
};

}  // namespace

std::unique_ptr<ObjectCatalog> makeEmbeddedCatalog() {
  return std::make_unique<EmbeddedCatalog>();
}

}  // namespace occlusion_env
