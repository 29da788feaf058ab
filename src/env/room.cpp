#include "occlusion_env/env/room.hpp"

#include <algorithm>
#include <cmath>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

constexpr int kNumWalls = 4;
constexpr double kFloorHalfSizeM = 14.0;   // the floor square's half side
constexpr double kWallHalfWidthM = 14.0;   // each wall's half width (walls cross at corners)
constexpr double kMinWallDistanceM = 2.0;  // wall distances from the origin ~ U(min, 2 R)
constexpr double kWallClearanceM = 0.3;    // between a wall and the nearest target
constexpr double kFloorDropM = 0.001;      // floor below the lowest point: no coplanar faces
constexpr int kMaxTilesPerSide = 24;

/// Linear RGB of an sRGB-like colour given in HSV (h in [0, 360), s, v in [0, 1]).
Eigen::Vector3f linearFromHsv(double h, double s, double v) {
  const double c = v * s;
  const double x = c * (1.0 - std::abs(std::fmod(h / 60.0, 2.0) - 1.0));
  const double m = v - c;
  double r = 0, g = 0, b = 0;
  if (h < 60) {
    r = c, g = x;
  } else if (h < 120) {
    r = x, g = c;
  } else if (h < 180) {
    g = c, b = x;
  } else if (h < 240) {
    g = x, b = c;
  } else if (h < 300) {
    r = x, b = c;
  } else {
    r = c, b = x;
  }
  const auto linear = [](double value) { return static_cast<float>(std::pow(value, 2.2)); };
  return {linear(r + m), linear(g + m), linear(b + m)};
}

/// A floor colour: wood, stone/tile or carpet.
Eigen::Vector3f floorColour(RandomSource& random) {
  switch (random.below(3)) {
    case 0:
      return linearFromHsv(random.uniform(18, 40), random.uniform(0.35, 0.7),
                           random.uniform(0.3, 0.75));
    case 1:
      return linearFromHsv(random.uniform(0, 360), random.uniform(0.0, 0.15),
                           random.uniform(0.4, 0.9));
    default:
      return linearFromHsv(random.uniform(0, 360), random.uniform(0.15, 0.5),
                           random.uniform(0.15, 0.6));
  }
}

/// Tiles (per-tile brightness, checker contrast) facing +z at `height`.
TiledSurface makeFloor(double height, RandomSource& random) {
  const Eigen::Vector3f base = floorColour(random);
  const double tile = std::max(random.uniform(0.25, 1.2), 2.0 * kFloorHalfSizeM / kMaxTilesPerSide);
  const double checker = random.uniform(0.0, 0.25);
  const double jitter = random.uniform(0.0, 0.12);
  const int tiles = static_cast<int>(std::ceil(2.0 * kFloorHalfSizeM / tile));
  TiledSurface floor;
  const float corner = static_cast<float>(-kFloorHalfSizeM);
  floor.origin = Eigen::Vector3f(corner, corner, static_cast<float>(height));
  floor.step_u = Eigen::Vector3f(static_cast<float>(tile), 0.0f, 0.0f);  // x
  floor.step_v = Eigen::Vector3f(0.0f, static_cast<float>(tile), 0.0f);  // y: faces +z
  floor.cells_u = floor.cells_v = tiles;
  floor.colors.resize(static_cast<std::size_t>(tiles) * tiles);
  for (int i = 0; i < tiles; ++i) {
    for (int j = 0; j < tiles; ++j) {
      const double shade =
          (((i + j) % 2 == 0) ? 1.0 : 1.0 - checker) * (1.0 + random.uniform(-jitter, jitter));
      floor.colors[static_cast<std::size_t>(j) * tiles + i] =
          (base * static_cast<float>(shade)).cwiseMin(1.0f);
    }
  }
  return floor;
}

/// How far the targets reach along the horizontal unit vector `direction` [m].
double reach(const Scene& scene, const Eigen::Vector3d& direction) {
  double farthest = 0.0;
  for (const SceneObject& object : scene.objects) {
    const Eigen::AlignedBox3d box = boundingBox(object.model->full).cast<double>();
    const Eigen::Vector3d half = 0.5 * box.sizes();
    const double extent = std::abs(direction.x()) * half.x() + std::abs(direction.y()) * half.y();
    farthest = std::max(farthest, object.position_m.dot(direction) + extent);
  }
  return farthest;
}

/// Four walls facing the origin at random angles and distances, painted panels, and a ceiling.
std::vector<TiledSurface> makeWalls(const Scene& scene, double floor_height, double camera_radius,
                                    RandomSource& random, std::vector<Eigen::Vector3d>& normals,
                                    std::vector<double>& distances) {
  const Eigen::Vector3f paint =
      linearFromHsv(random.uniform(0, 360), random.uniform(0.0, 0.3), random.uniform(0.45, 0.95));
  const double height = random.uniform(2.4, 3.5);
  const double panel = random.uniform(0.4, 1.5);
  const double jitter = random.uniform(0.0, 0.06);
  const double rotation = random.uniform(0.0, 2.0 * M_PI);
  std::vector<TiledSurface> walls;
  for (int k = 0; k < kNumWalls; ++k) {
    const double angle = rotation + k * 0.5 * M_PI + random.uniform(-0.3, 0.3);
    const Eigen::Vector3d outward(std::cos(angle), std::sin(angle), 0.0);
    const double distance =
        std::max(random.uniform(kMinWallDistanceM, std::max(2.0 * camera_radius, 2.5)),
                 reach(scene, outward) + kWallClearanceM);
    normals.push_back(outward);
    distances.push_back(distance);
    const Eigen::Vector3d along(-outward.y(), outward.x(), 0.0);  // left to right seen from inside
    const int panels = static_cast<int>(std::ceil(2.0 * kWallHalfWidthM / panel));
    // Panels from the left end as seen from the origin, rightwards (-along), floor to top: the
    // side (-along) x up = -outward faces the origin.
    TiledSurface wall;
    const Eigen::Vector3d left_end = distance * outward + kWallHalfWidthM * along;
    wall.origin = Eigen::Vector3d(left_end.x(), left_end.y(), floor_height).cast<float>();
    wall.step_u = (-panel * along).cast<float>();
    wall.step_v = Eigen::Vector3f(0.0f, 0.0f, static_cast<float>(height));
    wall.cells_u = panels;
    wall.cells_v = 1;
    for (int p = 0; p < panels; ++p) {
      const float shade = static_cast<float>(1.0 + random.uniform(-jitter, jitter));
      wall.colors.push_back((paint * shade).cwiseMin(1.0f));
    }
    walls.push_back(std::move(wall));
  }
  // A ceiling facing down: seen from below it, not drawn from above.
  const float top = static_cast<float>(floor_height + height);
  const float half = static_cast<float>(kFloorHalfSizeM);
  TiledSurface ceiling;
  ceiling.origin = Eigen::Vector3f(-half, -half, top);
  ceiling.step_u = Eigen::Vector3f(0.0f, 2.0f * half, 0.0f);  // y x x = -z: faces down
  ceiling.step_v = Eigen::Vector3f(2.0f * half, 0.0f, 0.0f);
  ceiling.colors = {linearFromHsv(0.0, 0.0, random.uniform(0.6, 0.95))};
  walls.push_back(std::move(ceiling));
  return walls;
}

/// Catalogue objects that are not targets, outside the camera's sphere and inside the walls.
void addClutter(const Scene& scene, double floor_height, double camera_radius, int count,
                const std::vector<Eigen::Vector3d>& normals, const std::vector<double>& distances,
                ObjectLibrary& library, RandomSource& random, Room& room) {
  const std::vector<ObjectInfo>& catalogue = library.catalog().objects();
  std::vector<const ObjectInfo*> candidates;
  for (const ObjectInfo& info : catalogue) {
    const bool is_target =
        std::any_of(scene.objects.begin(), scene.objects.end(),
                    [&](const SceneObject& o) { return o.model->info.id == info.id; });
    if (!is_target) candidates.push_back(&info);
  }
  if (candidates.empty()) return;
  for (int n = 0; n < count; ++n) {
    const ObjectInfo& info = *candidates[random.below(candidates.size())];
    std::shared_ptr<const ObjectModel> model = library.get(info.id);
    const Eigen::AlignedBox3d box = boundingBox(model->full).cast<double>();
    const double radius = 0.5 * box.sizes().head<2>().norm();  // any yaw
    const double yaw = random.uniform(0.0, 2.0 * M_PI);
    for (int attempt = 0; attempt < 16; ++attempt) {
      const double angle = random.uniform(0.0, 2.0 * M_PI);
      const double distance = camera_radius + radius + random.uniform(0.1, 3.0);
      const Eigen::Vector3d centre(distance * std::cos(angle), distance * std::sin(angle), 0.0);
      bool inside = true;
      for (std::size_t k = 0; k < normals.size(); ++k) {
        inside = inside && centre.dot(normals[k]) + radius < distances[k] - 0.05;
      }
      if (!inside) continue;
      SceneObject object;
      object.model = model;
      object.position_m = centre + Eigen::Vector3d(0, 0, floor_height + 0.5 * box.sizes().z());
      room.clutter.push_back(object);
      room.clutter_yaw_rad.push_back(yaw);
      break;
    }
  }
}

SceneLighting drawLighting(RandomSource& random) {
  SceneLighting light;
  light.headlight = false;
  const double azimuth = random.uniform(0.0, 2.0 * M_PI);
  const double elevation = random.uniform(0.5, 1.4);
  light.to_light_world =
      Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
                      std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
  const double warmth = random.uniform(-1.0, 1.0);  // cool (-) to warm (+)
  const double intensity = random.uniform(0.5, 0.95);
  light.color = Eigen::Vector3f(static_cast<float>(1.0 + 0.15 * warmth), 1.0f,
                                static_cast<float>(1.0 - 0.15 * warmth));
  light.diffuse = static_cast<float>(intensity);
  light.ambient = static_cast<float>(random.uniform(0.12, 0.4));
  return light;
}

}  // namespace

void WorldOptions::validate() const {
  if (world != "void" && world != "room") {
    throw InvalidArgumentError("option 'world' must be void or room, got " + quoted(world));
  }
  if (clutter < 0 || clutter > 8) {
    throw InvalidArgumentError("option 'clutter' must be in [0, 8], got " +
                               std::to_string(clutter));
  }
  if (!(floor_clearance_m >= 0.0 && std::isfinite(floor_clearance_m))) {
    throw InvalidArgumentError("option 'floor_clearance' must be a finite number >= 0 m, got " +
                               std::to_string(floor_clearance_m));
  }
}

SceneBackground Room::background() const {
  SceneBackground background;
  // Walls first: the floor beyond them then fails the depth test before it is shaded.
  background.tiled = walls;
  background.tiled.push_back(floor);
  for (std::size_t i = 0; i < clutter.size(); ++i) {
    PlacedMesh placed;
    placed.mesh = &clutter[i].model->render;
    placed.world_from_object = Eigen::Translation3d(clutter[i].position_m) *
                               Eigen::AngleAxisd(clutter_yaw_rad[i], Eigen::Vector3d::UnitZ());
    background.two_sided.push_back(placed);
  }
  background.lighting = lighting;
  return background;
}

double standOnFloor(Scene& scene) {
  double floor = std::numeric_limits<double>::infinity();
  std::vector<double> half_heights;
  for (const SceneObject& object : scene.objects) {
    const double half = 0.5 * boundingBox(object.model->full).sizes().z();
    half_heights.push_back(half);
    floor = std::min(floor, object.position_m.z() - half);
  }
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    scene.objects[i].position_m.z() = floor + half_heights[i];
  }
  return floor;
}

double lowestElevationAbove(const Room& room, double camera_radius_m, double clearance_m) {
  // The camera's height is camera_radius_m * sin(elevation).
  const double lowest_height = room.floor_height_m + clearance_m;
  return std::asin(std::clamp(lowest_height / camera_radius_m, -1.0, 1.0));
}

Room generateRoom(const Scene& scene, double floor_height_m, double camera_radius_m,
                  const WorldOptions& options, ObjectLibrary& library, RandomSource& random) {
  Room room;
  room.floor_height_m = floor_height_m - kFloorDropM;
  room.floor = makeFloor(room.floor_height_m, random);
  std::vector<Eigen::Vector3d> normals;
  std::vector<double> distances;
  room.walls = makeWalls(scene, room.floor_height_m, camera_radius_m, random, normals, distances);
  addClutter(scene, room.floor_height_m, camera_radius_m, options.clutter, normals, distances,
             library, random, room);
  room.lighting = drawLighting(random);
  return room;
}

}  // namespace occlusion_env
