// The per-frame labels of the training data and the one convention for direction labels.
//
// A direction in the camera's (azimuth, elevation) plane is the angle
//   theta = atan2(d_elevation, d_azimuth)   [rad], 0 = towards +azimuth, pi/2 = upwards,
// stored as (sin theta, cos theta) so that it has no wrap-around (doc/CONVENTIONS.md). A
// horizontal image flip mirrors the scene about the vertical plane through the camera and the
// scene centre: azimuth offsets change sign, elevation offsets do not, so theta -> pi - theta,
// i.e. (sin, cos) -> (sin, -cos).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "occlusion_env/env/scene_setup.hpp"
#include "occlusion_env/geometry/camera.hpp"

namespace occlusion_env {
namespace dataset {

struct Direction {
  double sin = 0.0;
  double cos = 1.0;
  double angle_rad = 0.0;  // atan2(sin, cos), in (-pi, pi]
};

/// The direction of the move (d_azimuth, d_elevation); nullopt for a zero or non-finite move.
std::optional<Direction> directionOf(double d_azimuth, double d_elevation);

/// The label of the horizontally flipped image.
Direction flippedHorizontally(const Direction& direction);

struct FrameLabels {
  int image_id = 0;
  SphericalPose pose;             // the camera's angles [rad]
  std::int64_t occlusion_px = 0;  // L (Eq. 9) [px]
  double smooth_loss_px = 0.0;    // L_s [px]
  double gradient_azimuth = 0.0;  // dL_s/d azimuth [px/rad]
  double gradient_elevation = 0.0;
  bool gradient_valid = false;
  std::optional<Direction> descent;  // of -grad L_s; none when the gradient is invalid
  int oracle_steps = -1;             // fewest steps to an unoccluded view; -1: none within reach
                                     // or not computed (has_oracle)
  std::optional<Direction> escape;   // the oracle's first step; none for 0 or -1 steps
  /// Every first move as short as the oracle's (OcclusionOracle::shortestFirstMoves): 1 for
  /// direction 2 pi k / size() of the one-step circle; empty for 0 or -1 steps and in datasets
  /// written before it was recorded.
  std::vector<std::uint8_t> shortest_first_moves;
  bool has_oracle = false;
  /// The frame's world, depth sensor and camera (radius, field of view, intrinsics, scene scale);
  /// none in datasets written before they were recorded.
  std::optional<SceneSetup> setup;
};

}  // namespace dataset
}  // namespace occlusion_env
