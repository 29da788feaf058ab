// The world around a scene's target objects: `void` (the paper's black emptiness) or `room` (a
// floor the objects stand on, walls, background clutter, procedural surface colours and a light,
// all drawn from the scene's seed). Only the targets count for occlusion: the renderer draws the
// room into colour and depth but never into the silhouettes (render/renderer.hpp, SceneBackground).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "occlusion_env/common/random.hpp"
#include "occlusion_env/render/renderer.hpp"
#include "occlusion_env/scene/object_library.hpp"
#include "occlusion_env/scene/scene.hpp"

namespace occlusion_env {

struct WorldOptions {
  std::string world = "void";  // void | room
  /// Background objects from the catalogue (never a target's model) per room, 0..8. They stand
  /// outside the camera's sphere, so they can never come between the camera and a target.
  int clutter = 3;
  /// The camera keeps at least this height above a room's floor [m, in the scene's own units]:
  /// no rig can take it below the floor (the floor is one-sided: from below it would be looked
  /// through). Poses lower than that are clamped to it, as poses beyond the elevation limit are.
  double floor_clearance_m = 0.1;

  /// Throws InvalidArgumentError for an unknown world, a clutter count outside 0..8 or a
  /// negative floor clearance.
  void validate() const;
  bool isRoom() const { return world == "room"; }
};

/// A room drawn for one scene. Walls and floor face inwards and are drawn one-sided, so a wall
/// between the camera and the targets is seen from behind and not drawn: no part of the room
/// hides a target from any camera pose.
struct Room {
  double floor_height_m = 0.0;  // world z of the floor
  TiledSurface floor;           // world frame, tiles with per-tile colour, facing up
  /// World frame: four walls at random distances and angles (painted panels, facing the
  /// origin), then a ceiling (facing down).
  std::vector<TiledSurface> walls;
  std::vector<SceneObject> clutter;
  std::vector<double> clutter_yaw_rad;  // per clutter object, about world z
  SceneLighting lighting;

  /// The renderer's view of the room; valid while this Room lives.
  SceneBackground background() const;
};

/// Moves each object vertically so that its lowest point lies on a common floor: the lowest
/// bottom among them. Returns the floor's height [m].
double standOnFloor(Scene& scene);

/// The lowest elevation [rad] at which a camera on a sphere of `camera_radius_m` about the origin
/// stays `clearance_m` above the room's floor (-pi/2 when the whole sphere does, pi/2 when none
/// of it does).
double lowestElevationAbove(const Room& room, double camera_radius_m, double clearance_m);

/// Draws a room around `scene` (standing on `floor_height_m`) for a camera on a sphere of
/// `camera_radius_m` about the origin.
Room generateRoom(const Scene& scene, double floor_height_m, double camera_radius_m,
                  const WorldOptions& options, ObjectLibrary& library, RandomSource& random);

}  // namespace occlusion_env
