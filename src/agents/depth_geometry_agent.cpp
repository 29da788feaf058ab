#include "occlusion_env/agents/depth_geometry_agent.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <memory>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/geometry/camera.hpp"

namespace occlusion_env {
namespace {

// Voxel coordinates packed 21 bits per axis, offset so that negative coordinates fit.
constexpr int kKeyBits = 21;
constexpr std::int64_t kKeyOffset = std::int64_t{1} << (kKeyBits - 1);
constexpr std::uint64_t kKeyMask = (std::uint64_t{1} << kKeyBits) - 1;
constexpr int kMaxObjects = 32;                    // one bit each in a pixel's word
constexpr std::int64_t kMaxGridCells = 1LL << 27;  // splitIntoObjects' scratch: 128 MiB at most

std::uint64_t packKey(std::int64_t x, std::int64_t y, std::int64_t z) {
  return (static_cast<std::uint64_t>(x + kKeyOffset) << (2 * kKeyBits)) |
         (static_cast<std::uint64_t>(y + kKeyOffset) << kKeyBits) |
         static_cast<std::uint64_t>(z + kKeyOffset);
}

Eigen::Vector3i unpackKey(std::uint64_t key) {
  return {
      static_cast<int>(static_cast<std::int64_t>((key >> (2 * kKeyBits)) & kKeyMask) - kKeyOffset),
      static_cast<int>(static_cast<std::int64_t>((key >> kKeyBits) & kKeyMask) - kKeyOffset),
      static_cast<int>(static_cast<std::int64_t>(key & kKeyMask) - kKeyOffset)};
}

// The centre [m] of the voxel at integer coordinates `cell`, voxels `voxel_m` on a side.
Eigen::Vector3d voxelCentre(const Eigen::Vector3i& cell, double voxel_m) {
  return (cell.cast<double>().array() + 0.5).matrix() * voxel_m;
}

// The index of cell `c` in a grid of `size` cells, x fastest.
std::int64_t cellIndex(const Eigen::Vector3i& c, const Eigen::Vector3i& size) {
  return (std::int64_t{c.z()} * size.y() + c.y()) * size.x() + c.x();
}

// grid (nx, ny, nz, x fastest) grown by `radius` cells along `axis`: a cell is set when any cell
// within `radius` along the axis is (a running count over the window).
void growAlongAxis(std::vector<std::uint8_t>& grid, const Eigen::Vector3i& size, int axis,
                   int radius, std::vector<std::uint8_t>& line_in) {
  const std::int64_t stride[3] = {1, size.x(), std::int64_t{size.x()} * size.y()};
  const int n = size[axis];
  const int a = axis == 0 ? 1 : 0;
  const int b = axis == 2 ? 1 : 2;
  line_in.resize(n);
  for (int j = 0; j < size[b]; ++j) {
    for (int i = 0; i < size[a]; ++i) {
      const std::int64_t base = i * stride[a] + j * stride[b];
      for (int k = 0; k < n; ++k) line_in[k] = grid[base + k * stride[axis]];
      int window = 0;  // set cells within [k - radius, k + radius]
      for (int k = 0; k < std::min(radius, n); ++k) window += line_in[k];
      for (int k = 0; k < n; ++k) {
        if (k + radius < n) window += line_in[k + radius];
        if (k - radius - 1 >= 0) window -= line_in[k - radius - 1];
        grid[base + k * stride[axis]] = window > 0 ? 1 : 0;
      }
    }
  }
}

}  // namespace

DepthGeometryAgent::DepthGeometryAgent(DepthGeometryOptions options)
    : options_(options), surfaces_(options.bounding_surfaces) {
  if (!(options_.voxel_fraction > 0.0 && options_.voxel_fraction <= 0.1))
    throw InvalidArgumentError("depth_geometry: voxel_fraction must be in (0, 0.1]");
  if (options_.join_voxels < 0 || options_.join_voxels > 50)
    throw InvalidArgumentError("depth_geometry: join_voxels must be in [0, 50]");
  if (options_.min_object_voxels < 1)
    throw InvalidArgumentError("depth_geometry: min_object_voxels must be at least 1");
  if (!(options_.step_size_rad > 0.0 && options_.step_size_rad < 1.0))
    throw InvalidArgumentError("depth_geometry: step_size_rad must be in (0, 1)");
  if (!(options_.search_radius_steps >= 1.0 && options_.search_radius_steps <= 60.0))
    throw InvalidArgumentError("depth_geometry: search_radius_steps must be in [1, 60]");
  if (!(options_.elevation_limit_rad >= 0.0 && options_.elevation_limit_rad < M_PI / 2))
    throw InvalidArgumentError("depth_geometry: elevation_limit_rad must be in [0, pi/2)");
  const int m = static_cast<int>(std::ceil(options_.search_radius_steps));
  for (int i = -m; i <= m; ++i) {
    for (int j = -m; j <= m; ++j) {
      const double d = std::hypot(i, j);
      if (d > 0.0 && d <= options_.search_radius_steps) lattice_.push_back({d, i, j});
    }
  }
  std::sort(lattice_.begin(), lattice_.end(), [](const LatticeOffset& p, const LatticeOffset& q) {
    if (p.distance_steps != q.distance_steps) return p.distance_steps < q.distance_steps;
    if (p.azimuth_steps != q.azimuth_steps) return p.azimuth_steps < q.azimuth_steps;
    return p.elevation_steps < q.elevation_steps;
  });
}

void DepthGeometryAgent::reset(std::uint64_t) {
  voxel_m_ = 0.0;
  occupied_.clear();
  visited_.clear();
  bounds_.clear();
  lowest_elevation_rad_ = -M_PI / 2;
  highest_elevation_rad_ = M_PI / 2;
  centres_.clear();
  object_of_.clear();
  objects_ = 0;
  last_move_ = {1.0, 0.0};
  plan_ = {};
}

void DepthGeometryAgent::integrate(const RigObservation& observation) {
  const CameraIntrinsics& k = observation.intrinsics;
  if (!(std::isfinite(k.fx) && std::isfinite(k.fy) && k.fx > 0.0 && k.fy > 0.0 &&
        std::isfinite(k.cx) && std::isfinite(k.cy)))
    throw InvalidArgumentError("depth_geometry needs the camera's intrinsics (finite fx, fy > 0)");
  const cv::Mat& depth = observation.depth;
  if (depth.type() != CV_32FC1 || depth.cols != k.width || depth.rows != k.height)
    throw InvalidArgumentError("depth_geometry needs 32FC1 depth of the intrinsics' size");
  const double radius = observation.world_from_optical.translation().norm();
  if (!(radius > 0.0 && std::isfinite(radius)))
    throw InvalidArgumentError(
        "depth_geometry needs the camera's pose on its sphere (world_from_optical)");
  if (voxel_m_ == 0.0) voxel_m_ = options_.voxel_fraction * radius;
  const Eigen::Matrix3d rotation = observation.world_from_optical.linear();
  const Eigen::Vector3d origin = observation.world_from_optical.translation();
  if (options_.skip_bounding_surfaces)
    noteBounds(surfaces_.find(depth, k, on_surface_), depth, k, observation.world_from_optical,
               radius);
  for (int v = 0; v < depth.rows; ++v) {
    const float* row = depth.ptr<float>(v);
    const double ray_y = (v - k.cy) / k.fy;
    for (int u = 0; u < depth.cols; ++u) {
      const double z = row[u];
      if (!(z > 0.0) || !std::isfinite(z)) continue;  // no reading
      const Eigen::Vector3d world =
          origin + rotation * Eigen::Vector3d((u - k.cx) / k.fx * z, ray_y * z, z);
      if (world.norm() >= radius) continue;  // beyond the sphere: not among the objects
      if (!bounds_.empty() && onOrBehindBound(world, z)) continue;  // a floor or a wall
      occupied_.insert(packKey(static_cast<std::int64_t>(std::floor(world.x() / voxel_m_)),
                               static_cast<std::int64_t>(std::floor(world.y() / voxel_m_)),
                               static_cast<std::int64_t>(std::floor(world.z() / voxel_m_))));
    }
  }
}

bool DepthGeometryAgent::onOrBehindBound(const Eigen::Vector3d& world, double z_m) const {
  return std::any_of(bounds_.begin(), bounds_.end(), [&](const Bound& bound) {
    return bound.normal.dot(world) + bound.offset_m < voxel_m_ + bound.spread_per_m2 * z_m * z_m;
  });
}

void DepthGeometryAgent::collectSurfacePoints(const std::vector<SurfacePlane>& planes,
                                              const cv::Mat& depth, const CameraIntrinsics& k,
                                              const Eigen::Isometry3d& world_from_optical) {
  std::vector<std::vector<Eigen::Vector4d>>& points = scratch_.surface_points;
  points.resize(planes.size());
  for (auto& p : points) p.clear();
  for (int v = 0; v < depth.rows; ++v) {
    const float* row = depth.ptr<float>(v);
    const std::uint8_t* surface = on_surface_.ptr<std::uint8_t>(v);
    for (int u = 0; u < depth.cols; ++u) {
      if (surface[u] == 0) continue;
      const double z = row[u];
      const Eigen::Vector3d point((u - k.cx) / k.fx * z, (v - k.cy) / k.fy * z, z);
      std::size_t nearest = 0;
      double distance = HUGE_VAL;
      for (std::size_t i = 0; i < planes.size(); ++i) {
        const double d = std::abs(planes[i].normal.dot(point) + planes[i].offset_m);
        if (d < distance) distance = d, nearest = i;
      }
      const Eigen::Vector3d world = world_from_optical * point;
      points[nearest].emplace_back(world.x(), world.y(), world.z(), z);
    }
  }
}

void DepthGeometryAgent::noteBounds(const std::vector<SurfacePlane>& planes, const cv::Mat& depth,
                                    const CameraIntrinsics& k,
                                    const Eigen::Isometry3d& world_from_optical, double radius) {
  if (planes.empty()) return;
  collectSurfacePoints(planes, depth, k, world_from_optical);
  const std::vector<std::vector<Eigen::Vector4d>>& points = scratch_.surface_points;
  std::vector<double>& values = scratch_.values;
  const auto median = [&values]() {
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    return values[values.size() / 2];
  };
  const double max_tilt_rad = 10.0 * M_PI / 180.0;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    if (points[i].size() < 3) continue;
    // A room's floor and ceiling are level and its walls upright: the plane found is snapped to
    // the nearest of those; a plane tilted more than 10 degrees from both is no bound.
    Eigen::Vector3d normal = world_from_optical.linear() * planes[i].normal;
    if (std::abs(normal.z()) > std::cos(max_tilt_rad)) {
      normal = Eigen::Vector3d(0.0, 0.0, normal.z() > 0.0 ? 1.0 : -1.0);
    } else if (std::abs(normal.z()) < std::sin(max_tilt_rad)) {
      normal = Eigen::Vector3d(normal.x(), normal.y(), 0.0).normalized();
    } else {
      continue;
    }
    values.clear();
    for (const Eigen::Vector4d& p : points[i]) values.push_back(-normal.dot(p.head<3>()));
    Bound bound{normal, median(), 0.0};
    // A surface with the sphere's centre behind it bounds nothing the camera circles.
    if (!(bound.offset_m > 0.0)) continue;
    values.clear();
    for (const Eigen::Vector4d& p : points[i])
      values.push_back(std::abs(normal.dot(p.head<3>()) + bound.offset_m) / (p.w() * p.w()));
    bound.spread_per_m2 = 3.0 * 1.4826 * median();  // 3 sigma, sigma from the median deviation
    const double tolerance_m = voxel_m_ + bound.spread_per_m2 * radius * radius;
    const bool known = std::any_of(bounds_.begin(), bounds_.end(), [&](const Bound& b) {
      return b.normal.dot(bound.normal) > 0.999 &&
             std::abs(b.offset_m - bound.offset_m) < tolerance_m;
    });
    if (known) continue;
    bounds_.push_back(bound);
    // The voxels fused before it was found, at the tolerance of a point at the sphere's radius.
    for (auto it = occupied_.begin(); it != occupied_.end();) {
      const Eigen::Vector3d centre = voxelCentre(unpackKey(*it), voxel_m_);
      it = bound.normal.dot(centre) + bound.offset_m < tolerance_m ? occupied_.erase(it)
                                                                   : std::next(it);
    }
  }
}

void DepthGeometryAgent::labelGrownParts(const Eigen::Vector3i& size) {
  const std::vector<Eigen::Vector3i>& cells = scratch_.cells;
  const auto index = [&](const Eigen::Vector3i& c) { return cellIndex(c, size); };
  labels_.assign(grid_.size(), -1);
  std::vector<int>& voxels_per_label = scratch_.voxels_per_label;
  voxels_per_label.clear();
  std::vector<Eigen::Vector3i>& stack = scratch_.stack;  // cells of the part still to visit
  std::vector<int>& label_of_voxel = scratch_.label_of_voxel;
  label_of_voxel.resize(cells.size());
  // Labels every grown cell 26-connected to `seed` with `label`.
  const auto flood = [&](const Eigen::Vector3i& seed, int label) {
    labels_[index(seed)] = label;
    stack.push_back(seed);
    while (!stack.empty()) {
      const Eigen::Vector3i c = stack.back();
      stack.pop_back();
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const Eigen::Vector3i n = c + Eigen::Vector3i(dx, dy, dz);
            if ((n.array() < 0).any() || (n.array() >= size.array()).any()) continue;
            const std::int64_t j = index(n);
            if (!grid_[j] || labels_[j] >= 0) continue;
            labels_[j] = label;
            stack.push_back(n);
          }
    }
  };
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::int64_t start = index(cells[i]);
    if (labels_[start] < 0) {
      flood(cells[i], static_cast<int>(voxels_per_label.size()));
      voxels_per_label.push_back(0);
    }
    label_of_voxel[i] = labels_[start];
    ++voxels_per_label[labels_[start]];
  }
}

void DepthGeometryAgent::splitIntoObjects() {
  centres_.clear();
  object_of_.clear();
  objects_ = 0;
  if (occupied_.empty()) return;
  // Sorted, so that the objects come out in the same order whatever the set's order.
  std::vector<std::uint64_t>& keys = scratch_.keys;
  keys.assign(occupied_.begin(), occupied_.end());
  std::sort(keys.begin(), keys.end());
  std::vector<Eigen::Vector3i>& cells = scratch_.cells;
  cells.resize(keys.size());
  Eigen::Vector3i low = unpackKey(keys.front()), high = low;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    cells[i] = unpackKey(keys[i]);
    low = low.cwiseMin(cells[i]);
    high = high.cwiseMax(cells[i]);
  }
  const int pad = options_.join_voxels;
  low.array() -= pad;
  const Eigen::Vector3i size = (high - low).array() + 1 + pad;
  const std::int64_t cell_count = std::int64_t{size.x()} * size.y() * size.z();
  if (cell_count > kMaxGridCells)
    throw InvalidArgumentError("depth_geometry: the depth spans more than its voxel grid can hold");
  const auto index = [&](const Eigen::Vector3i& c) { return cellIndex(c, size); };
  grid_.assign(cell_count, 0);
  for (auto& c : cells) {
    c -= low;
    grid_[index(c)] = 1;
  }
  std::vector<std::uint8_t>& line = scratch_.line;
  for (int axis = 0; axis < 3 && pad > 0; ++axis) growAlongAxis(grid_, size, axis, pad, line);

  labelGrownParts(size);
  const std::vector<int>& voxels_per_label = scratch_.voxels_per_label;
  const std::vector<int>& label_of_voxel = scratch_.label_of_voxel;

  // The largest parts of at least min_object_voxels, at most kMaxObjects of them.
  std::vector<int>& order = scratch_.order;
  order.resize(voxels_per_label.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](int p, int q) { return voxels_per_label[p] > voxels_per_label[q]; });
  std::vector<int>& object_of_label = scratch_.object_of_label;
  object_of_label.assign(voxels_per_label.size(), -1);
  for (int label : order) {
    if (objects_ == kMaxObjects || voxels_per_label[label] < options_.min_object_voxels) break;
    object_of_label[label] = objects_++;
  }
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const int object = object_of_label[label_of_voxel[i]];
    if (object < 0) continue;
    centres_.push_back(voxelCentre(cells[i] + low, voxel_m_));
    object_of_.push_back(object);
  }
}

int DepthGeometryAgent::overlapPixels(const Eigen::Isometry3d& world_from_optical,
                                      const CameraIntrinsics& k, int stop_at) {
  const std::size_t pixels = static_cast<std::size_t>(k.width) * k.height;
  if (pixel_stamp_.size() != pixels || ++stamp_ == 0) {
    pixel_stamp_.assign(pixels, 0);
    pixel_objects_.assign(pixels, 0);
    stamp_ = 1;
  }
  const Eigen::Isometry3d optical_from_world = world_from_optical.inverse();
  const Eigen::Matrix3d rotation = optical_from_world.linear();
  const Eigen::Vector3d translation = optical_from_world.translation();
  // Each voxel covers the (2 r + 1)^2 pixels around its centre's projection, r half its
  // footprint at the sphere's radius rounded (2 cm at 4 m: 1.1 px at 256 px and 60 deg), so that
  // neighbouring voxels leave no holes; and at least 1, so that objects touching in the image
  // count as overlapping (the nearer one may hide more of the other; with 0, a move along the line
  // where two patches touch looked like parting them: the unit test's patches).
  const int r = std::max(1, static_cast<int>(std::lround(0.5 * k.fx * options_.voxel_fraction)));
  int overlapping = 0;
  for (std::size_t i = 0; i < centres_.size(); ++i) {
    const Eigen::Vector3d p = rotation * centres_[i] + translation;
    if (p.z() <= 1e-6) continue;
    const Eigen::Vector2d pixel = k.project(p);
    const int u0 = static_cast<int>(std::lround(pixel.x()));
    const int v0 = static_cast<int>(std::lround(pixel.y()));
    if (u0 < -r || v0 < -r || u0 >= k.width + r || v0 >= k.height + r) continue;
    const std::uint32_t bit = std::uint32_t{1} << object_of_[i];
    for (int v = std::max(0, v0 - r); v <= std::min(k.height - 1, v0 + r); ++v) {
      for (int u = std::max(0, u0 - r); u <= std::min(k.width - 1, u0 + r); ++u) {
        const std::size_t j = static_cast<std::size_t>(v) * k.width + u;
        if (pixel_stamp_[j] != stamp_) {
          pixel_stamp_[j] = stamp_;
          pixel_objects_[j] = bit;
          continue;
        }
        const std::uint32_t seen = pixel_objects_[j];
        if (seen & bit) continue;
        if ((seen & (seen - 1)) == 0 && ++overlapping >= stop_at) return overlapping;
        pixel_objects_[j] = seen | bit;
      }
    }
  }
  return overlapping;
}

void DepthGeometryAgent::noteElevationLimits(const SphericalPose& pose) {
  if (visited_.empty()) return;
  // The rig moves along the unit move asked for, whatever its step; a move that was stopped in
  // elevation (or not made at all) turned away from it by more than a tenth in elevation. A move
  // stopped part of the way straight up or down is noted at the next one, which is not made.
  const double made_azimuth = azimuthChange(visited_.back(), pose);
  const double made_elevation = pose.elevation_rad - visited_.back().elevation_rad;
  const double length = std::hypot(made_azimuth, made_elevation);
  const double asked = last_move_.d_elevation_rad;
  const double made = length > 1e-9 ? made_elevation / length : 0.0;  // direction's elevation
  if (asked < 0.0 && made > asked + 0.1)
    lowest_elevation_rad_ = std::max(lowest_elevation_rad_, pose.elevation_rad);
  if (asked > 0.0 && made < asked - 0.1)
    highest_elevation_rad_ = std::min(highest_elevation_rad_, pose.elevation_rad);
}

Action DepthGeometryAgent::act(const RigObservation& observation) {
  noteElevationLimits(observation.pose);
  integrate(observation);
  splitIntoObjects();
  visited_.push_back(observation.pose);
  plan_ = {};
  plan_.voxels = static_cast<int>(occupied_.size());
  plan_.objects = objects_;
  if (objects_ < 2) return last_move_;  // nothing to part: keep going

  const double radius = observation.world_from_optical.translation().norm();
  const SphericalCamera camera(radius, options_.elevation_limit_rad);
  const double h = options_.step_size_rad;
  int best = INT_MAX;
  const LatticeOffset* target = nullptr;
  for (const LatticeOffset& offset : lattice_) {
    const SphericalPose pose{observation.pose.azimuth_rad + offset.azimuth_steps * h,
                             observation.pose.elevation_rad + offset.elevation_steps * h};
    if (std::abs(pose.elevation_rad) > options_.elevation_limit_rad) continue;
    if (pose.elevation_rad < lowest_elevation_rad_ - 1e-9 ||
        pose.elevation_rad > highest_elevation_rad_ + 1e-9)
      continue;  // beyond a limit the rig met
    // A view of this episode did not end it: it is not the clear view the voxels missed.
    const bool visited = std::any_of(visited_.begin(), visited_.end(), [&](const SphericalPose& v) {
      return std::hypot(azimuthChange(v, pose), v.elevation_rad - pose.elevation_rad) < 0.5 * h;
    });
    if (visited) continue;
    const int overlapping =
        overlapPixels(camera.worldFromOptical(pose), observation.intrinsics, best);
    if (overlapping < best) {
      best = overlapping;
      target = &offset;
      if (best == 0) break;
    }
  }
  if (target == nullptr) return last_move_;
  plan_.found_clear_pose = best == 0;
  plan_.overlap_px = best;
  plan_.target_d_azimuth_rad = target->azimuth_steps * h;
  plan_.target_d_elevation_rad = target->elevation_steps * h;
  const double length = target->distance_steps;
  last_move_ = {target->azimuth_steps / length, target->elevation_steps / length};
  return last_move_;
}

AgentEntry depthGeometryAgentEntry() {
  AgentEntry entry;
  entry.name = "depth_geometry";
  entry.summary =
      "a unit move towards the nearest pose of the rig's step lattice from which no two objects "
      "overlap, planned on voxels fused from the depth of the episode's views and split into "
      "objects by the gaps between them (no network, no simulator)";
  entry.make = [](const AgentCapabilities&) { return std::make_unique<DepthGeometryAgent>(); };

  return entry;
}

}  // namespace occlusion_env
