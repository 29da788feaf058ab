#include "occlusion_env/dataset/labels.hpp"

#include <cmath>

namespace occlusion_env {
namespace dataset {

std::optional<Direction> directionOf(double d_azimuth, double d_elevation) {
  const double length = std::hypot(d_azimuth, d_elevation);
  if (!std::isfinite(length) || length == 0.0) return std::nullopt;
  Direction direction;
  direction.sin = d_elevation / length;
  direction.cos = d_azimuth / length;
  direction.angle_rad = std::atan2(d_elevation, d_azimuth);
  return direction;
}

Direction flippedHorizontally(const Direction& direction) {
  Direction flipped;
  flipped.sin = direction.sin;
  flipped.cos = -direction.cos;
  flipped.angle_rad = std::atan2(flipped.sin, flipped.cos);
  return flipped;
}

}  // namespace dataset
}  // namespace occlusion_env
