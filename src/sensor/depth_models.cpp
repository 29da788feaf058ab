// The depth-sensor models (doc/SENSORS.md): structured light, active stereo, time of flight.
#include <algorithm>
#include <cmath>
#include <limits>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/sensor/camera_sensor.hpp"

namespace occlusion_env {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kMaxIncidenceRad = 0.5 * M_PI - 0.05;  // keeps theta / (pi/2 - theta) finite

bool hasDepth(float z) {
  return z > 0.0f;  // false for NaN
}

/// Rounds positive depths to a step [m] (none for a step of 0), inline: no libm call per pixel.
class Quantiser {
  static constexpr float kMaxSteps = 1e9f;

 public:
  explicit Quantiser(double step_m)
      : step_(static_cast<float>(step_m)), inverse_(step_m > 0.0 ? 1.0f / step_ : 0.0f) {}
  float operator()(float z) const {
    // Half up (= std::round for positive z), branch-free; a step so fine that z / step leaves
    // the int32 range (or no step, or no depth) leaves z.
    const float steps = std::min(z * inverse_, kMaxSteps);
    const float rounded = static_cast<float>(static_cast<std::int32_t>(steps + 0.5f)) * step_;
    return (steps > 0.0f) & (steps < kMaxSteps) ? rounded : z;
  }

 private:
  float step_;
  float inverse_;
};

float incidenceAngle(float cos_incidence) {
  return std::min(std::acos(std::clamp(cos_incidence, 0.0f, 1.0f)),
                  static_cast<float>(kMaxIncidenceRad));
}

/// Marks in `shadow` (CV_8UC1, 1 = hidden) the pixels that a second viewpoint `baseline_m` along
/// +x (a projector or the right imager) cannot see, from the ideal depth: scanning each row from
/// the right, a pixel whose column in the other view lies beyond the nearest one seen so far is
/// behind a nearer surface there. Also marks what falls left of the other view's image.
/// `columns` (one row long) is scratch.
void markHiddenFromSecondView(const cv::Mat& depth, double fx, double baseline_m,
                              bool outside_is_hidden, std::vector<float>& columns,
                              cv::Mat& shadow) {
  shadow.create(depth.size(), CV_8UC1);
  columns.resize(depth.cols);
  const float shift = static_cast<float>(fx * baseline_m);
  constexpr float kNone = -std::numeric_limits<float>::infinity();
  for (int v = 0; v < depth.rows; ++v) {
    const float* z = depth.ptr<float>(v);
    std::uint8_t* hidden = shadow.ptr<std::uint8_t>(v);
    float* column = columns.data();
    for (int u = 0; u < depth.cols; ++u) {  // vectorised: each pixel's column in the other view
      column[u] = hasDepth(z[u]) ? static_cast<float>(u) - shift / z[u] : kNone;
    }
    float nearest_column = std::numeric_limits<float>::infinity();
    for (int u = depth.cols - 1; u >= 0; --u) {
      const bool behind = column[u] > nearest_column ||
                          (outside_is_hidden && column[u] < 0.0f && column[u] > kNone);
      hidden[u] = behind ? 1 : 0;
      if (!behind && column[u] > kNone) nearest_column = column[u];
    }
  }
}

/// `band` = `mask` dilated by a (2r + 1)^2 square; `scratch` holds the horizontal pass.
void dilateSquare(const cv::Mat& mask, int radius, cv::Mat& scratch, cv::Mat& band) {
  scratch.create(mask.size(), CV_8UC1);
  band.create(mask.size(), CV_8UC1);
  const int w = mask.cols;
  const int h = mask.rows;
  for (int v = 0; v < h; ++v) {  // OR of the columns within the radius, clipped at the border
    const std::uint8_t* in = mask.ptr<std::uint8_t>(v);
    std::uint8_t* out = scratch.ptr<std::uint8_t>(v);
    std::copy(in, in + w, out);
    for (int k = 1; k <= radius && k < w; ++k) {
      for (int u = 0; u + k < w; ++u) out[u] |= in[u + k];
      for (int u = k; u < w; ++u) out[u] |= in[u - k];
    }
  }
  for (int v = 0; v < h; ++v) {  // row by row: OR of the rows within the radius
    std::uint8_t* out = band.ptr<std::uint8_t>(v);
    std::fill(out, out + w, std::uint8_t{0});
    for (int k = std::max(v - radius, 0); k <= std::min(v + radius, h - 1); ++k) {
      const std::uint8_t* row = scratch.ptr<std::uint8_t>(k);
      for (int u = 0; u < w; ++u) out[u] |= row[u];
    }
  }
}

class KinectV1Model : public DepthSensorModel {
 public:
  explicit KinectV1Model(const KinectV1Parameters& p) : p_(p), quantised_(p.quantisation_m) {}
  std::string name() const override { return "kinect_v1"; }

  // Random bits of pixel p: counter 2p (the two lateral draws), 2p + 1 (axial draw, hole).
  void measure(const cv::Mat& ideal, const cv::Mat& /*rgb*/, const CameraIntrinsics& intrinsics,
               const DepthGeometry& geometry, const CounterNoise& noise,
               cv::Mat& measured) override {
    measured.create(ideal.size(), CV_32FC1);
    const float pixel_scale =
        static_cast<float>(intrinsics.fx / p_.focal_length_px);  // sensor px -> rendered px
    const int w = ideal.cols;
    const int h = ideal.rows;
    for (int v = 0; v < h; ++v) {
      const float* cos_incidence = geometry.cos_incidence.ptr<float>(v);
      float* out = measured.ptr<float>(v);
      for (int u = 0; u < w; ++u) {
        const std::uint64_t pixel = static_cast<std::uint64_t>(v) * w + u;
        // Lateral noise: the reading comes from a jittered point of the surface.
        const float theta = incidenceAngle(cos_incidence[u]);
        const float grazing = theta / (static_cast<float>(0.5 * M_PI) - theta);
        const float sigma_lateral =
            static_cast<float>(p_.lateral_constant_px + p_.lateral_grazing_px * grazing) *
            pixel_scale;
        const std::uint64_t lateral = noise.bits(2 * pixel);
        const int su = std::clamp(
            u + roundToInt(sigma_lateral * byteSumNormal(static_cast<std::uint32_t>(lateral))), 0,
            w - 1);
        const int sv =
            std::clamp(v + roundToInt(sigma_lateral *
                                      byteSumNormal(static_cast<std::uint32_t>(lateral >> 32))),
                       0, h - 1);
        out[u] = axialReading(ideal.at<float>(sv, su), grazing, noise.bits(2 * pixel + 1));
      }
    }
    // The projector's shadow: no pattern, no depth.
    markHiddenFromSecondView(ideal, intrinsics.fx, p_.projector_baseline_m, false, columns_,
                             shadow_);
    for (int v = 0; v < h; ++v) {
      const std::uint8_t* shadowed = shadow_.ptr<std::uint8_t>(v);
      float* out = measured.ptr<float>(v);
      for (int u = 0; u < w; ++u) {
        if (shadowed[u]) out[u] = kNaN;
      }
    }
  }

  /// sigma_z of Nguyen et al. at depth z and grazing ratio theta / (pi/2 - theta).
  double axialSigma(double z, double grazing) const {
    return p_.axial_constant_m +
           p_.axial_quadratic_m * (z - p_.axial_offset_m) * (z - p_.axial_offset_m) +
           p_.grazing_coefficient_m / std::sqrt(z) * grazing * grazing;
  }

 private:
  static int roundToInt(float x) { return static_cast<int>(x + (x < 0.0f ? -0.5f : 0.5f)); }

  /// Low 32 bits: the axial draw; top 24: the hole draw.
  float axialReading(float z, float grazing, std::uint64_t bits) const {
    if (!hasDepth(z) || z < p_.min_range_m || z > p_.max_range_m) return kNaN;
    const float noisy = z + static_cast<float>(axialSigma(z, grazing)) *
                                byteSumNormal(static_cast<std::uint32_t>(bits));
    if (uniform24(bits) < p_.hole_rate) return kNaN;
    return quantised_(noisy);
  }

  KinectV1Parameters p_;
  Quantiser quantised_;
  std::vector<float> columns_;
  cv::Mat shadow_;
};

class RealSenseD435Model : public DepthSensorModel {
 public:
  explicit RealSenseD435Model(const RealSenseD435Parameters& p)
      : p_(p),
        quantised_(p.quantisation_m),
        cos_grazing_(static_cast<float>(std::cos(p.grazing_angle_rad))) {}
  std::string name() const override { return "realsense_d435"; }

  // Random bits of pixel (u, v): 32 of counter v * ceil(width / 2) + u / 2, the low half for
  // even u (the low byte: the disparity draw; the top 24 bits: the dropout draw).
  void measure(const cv::Mat& ideal, const cv::Mat& rgb, const CameraIntrinsics& intrinsics,
               const DepthGeometry& geometry, const CounterNoise& noise,
               cv::Mat& measured) override {
    measured.create(ideal.size(), CV_32FC1);
    // The band (edge_band_px sensor px either side of a discontinuity) in rendered px: the edge
    // pixels and band_radius more, the dropout scaled by the share of their width the band
    // covers, so that a render of any size loses at its edges the share of its pixels the
    // sensor's own image loses there (rounded up to whole pixels at the full probability, a
    // 128 px render lost 2.6 times the share a 512 px one did).
    const double band_px = p_.edge_band_px * intrinsics.fx / p_.focal_length_px;
    const int band_radius = std::max(0, static_cast<int>(std::ceil(band_px)) - 1);
    const float edge_dropout = static_cast<float>(p_.edge_dropout_probability *
                                                  std::min(1.0, band_px / (1 + band_radius)));
    dilateSquare(geometry.edge, band_radius, scratch_, edge_band_);
    // The right imager's view: occluded there or outside its image (the left band) = no match.
    markHiddenFromSecondView(ideal, intrinsics.fx, p_.baseline_m, true, columns_, hidden_);
    const bool read_rgb = !rgb.empty() && rgb.size() == ideal.size();
    for (int v = 0; v < ideal.rows; ++v) {
      const std::uint64_t first = static_cast<std::uint64_t>(v) * ((ideal.cols + 1) / 2);
      measureRow(ideal.ptr<float>(v), edge_band_.ptr<std::uint8_t>(v), hidden_.ptr<std::uint8_t>(v),
                 geometry.cos_incidence.ptr<float>(v),
                 read_rgb ? rgb.ptr<std::uint8_t>(v) : nullptr, noise, first, ideal.cols,
                 edge_dropout, measured.ptr<float>(v));
    }
  }

 private:
  // Two passes over a row: the random draws (scalar: 64-bit hashes), then the model, branch-free
  // so that it vectorises. `edge_dropout`: the probability in the edge band, this frame's.
  void measureRow(const float* z, const std::uint8_t* band, const std::uint8_t* hidden,
                  const float* cos_incidence, const std::uint8_t* colour, const CounterNoise& noise,
                  std::uint64_t first, int width, float edge_dropout, float* out) {
    normal_.resize(width);
    draw_.resize(width);
    // Rec. 709 luminance x 10000 against the threshold, in integers; a dark pixel's dropout draw
    // is compared with the larger probability, shown here by lowering the draw.
    const int dark_below = static_cast<int>(std::ceil(p_.dark_luminance * 255.0 * 10000.0));
    const float dark = static_cast<float>(p_.dark_dropout_probability);
    const std::array<float, 256>& levels = standardNormalLevels();
    for (int u = 0; u < width; u += 2) {
      const std::uint64_t bits = noise.bits(first + u / 2);
      normal_[u] = levels[bits & 0xff];
      draw_[u] = static_cast<float>((bits >> 8) & 0xffffff) * (1.0f / 16777216.0f);
      if (u + 1 < width) {
        normal_[u + 1] = levels[(bits >> 32) & 0xff];
        draw_[u + 1] = uniform24(bits);
      }
    }
    if (colour) {
      // Dropped if draw < p for the largest p that applies: a dark pixel is dropped anyway when
      // draw < dark, so its draw can be replaced by -1 there (and kept above).
      for (int u = 0; u < width; ++u) {
        const bool is_dark =
            2126 * colour[3 * u] + 7152 * colour[3 * u + 1] + 722 * colour[3 * u + 2] < dark_below;
        if (is_dark && draw_[u] < dark) draw_[u] = -1.0f;
      }
    }
    const float cos_grazing = cos_grazing_;
    const float min_range = static_cast<float>(p_.min_range_m);
    const float max_range = static_cast<float>(p_.max_range_m);
    const float hole = static_cast<float>(p_.hole_rate);
    const float edge = std::max(hole, edge_dropout);
    const float grazing = static_cast<float>(p_.grazing_dropout_probability);
    const float f_b = static_cast<float>(p_.focal_length_px * p_.baseline_m);
    const float sigma = static_cast<float>(p_.disparity_sigma_px);
    const float* normal = normal_.data();
    const float* draw = draw_.data();
    for (int u = 0; u < width; ++u) {
      // No reading outside the range (false for NaN), where the right imager is blind, or where
      // matching fails.
      const bool in_range =
          hasDepth(z[u]) & (z[u] >= min_range) & (z[u] <= max_range) & (hidden[u] == 0);
      const float edge_or_hole = band[u] ? edge : hole;
      const float dropout =
          cos_incidence[u] < cos_grazing ? std::max(edge_or_hole, grazing) : edge_or_hole;
      // Depth from a disparity (in the sensor's pixels) with noise: z = f B / (d + e).
      const float disparity = f_b / z[u] + sigma * normal[u];
      const float reading = quantised_(f_b / disparity);
      out[u] = in_range & (draw[u] >= dropout) ? reading : kNaN;
    }
  }

  RealSenseD435Parameters p_;
  Quantiser quantised_;
  float cos_grazing_;
  std::vector<float> columns_;
  std::vector<float> normal_;  // per pixel of a row: the disparity draw
  std::vector<float> draw_;    // the dropout draw (-1 where a dark surface drops it)
  cv::Mat scratch_;
  cv::Mat edge_band_;
  cv::Mat hidden_;
};

class AzureKinectModel : public DepthSensorModel {
 public:
  explicit AzureKinectModel(const AzureKinectParameters& p) : p_(p), quantised_(p.quantisation_m) {}
  std::string name() const override { return "azure_kinect"; }

  // Random bits of pixel p: counter 2p (low 32 bits: the axial draw; top 24: the hole draw),
  // 2p + 1 at an edge (bits 0-23: flying, invalid or kept; top 24: the flying pixel's mix).
  void measure(const cv::Mat& ideal, const cv::Mat& /*rgb*/, const CameraIntrinsics& intrinsics,
               const DepthGeometry& geometry, const CounterNoise& noise,
               cv::Mat& measured) override {
    measured.create(ideal.size(), CV_32FC1);
    const int radius = std::max(
        1,
        static_cast<int>(std::lround(p_.multipath_radius_px * intrinsics.fx / p_.focal_length_px)));
    // A discontinuity spoils the sensor pixels that straddle it: of a rendered pixel coarser
    // than the sensor's, the share of its width one sensor pixel is.
    const double edge_share = std::min(1.0, intrinsics.fx / p_.focal_length_px);
    const float flying = static_cast<float>(p_.flying_pixel_probability * edge_share);
    const float invalid = static_cast<float>(
        (p_.flying_pixel_probability + p_.edge_invalid_probability) * edge_share);
    for (int v = 0; v < ideal.rows; ++v) {
      const float* z = ideal.ptr<float>(v);
      const std::uint8_t* edge = geometry.edge.ptr<std::uint8_t>(v);
      float* out = measured.ptr<float>(v);
      for (int u = 0; u < ideal.cols; ++u) {
        out[u] = kNaN;
        if (!hasDepth(z[u])) continue;
        const std::uint64_t pixel = static_cast<std::uint64_t>(v) * ideal.cols + u;
        float reading = z[u];
        if (edge[u]) {
          // A pixel that straddles an edge integrates both surfaces.
          const std::uint64_t edge_bits = noise.bits(2 * pixel + 1);
          const float draw = static_cast<float>(edge_bits & 0xffffff) * (1.0f / 16777216.0f);
          if (draw >= invalid) {
            // kept as it is
          } else if (draw >= flying) {
            continue;
          } else {
            reading = flyingPixel(ideal, u, v, uniform24(edge_bits));
          }
        } else {
          reading += static_cast<float>(p_.multipath_gain) * concavity(ideal, u, v, radius);
        }
        if (reading < p_.min_range_m || reading > p_.max_range_m) continue;
        const std::uint64_t bits = noise.bits(2 * pixel);
        reading += static_cast<float>(axialSigma(reading)) *
                   byteSumNormal(static_cast<std::uint32_t>(bits));
        if (uniform24(bits) < p_.hole_rate) continue;
        out[u] = quantised_(reading);
      }
    }
  }

  double axialSigma(double z) const { return p_.axial_constant_m + p_.axial_linear * z; }

 private:
  /// A depth between the nearest and farthest surface of the 3x3 neighbourhood (NaN = ignored),
  /// `mix` of the way from the nearest.
  static float flyingPixel(const cv::Mat& ideal, int u, int v, float mix) {
    float nearest = std::numeric_limits<float>::infinity();
    float farthest = 0.0f;
    for (int dv = -1; dv <= 1; ++dv) {
      for (int du = -1; du <= 1; ++du) {
        const int nu = std::clamp(u + du, 0, ideal.cols - 1);
        const int nv = std::clamp(v + dv, 0, ideal.rows - 1);
        const float z = ideal.at<float>(nv, nu);
        if (!hasDepth(z)) continue;
        nearest = std::min(nearest, z);
        farthest = std::max(farthest, z);
      }
    }
    return nearest + mix * (farthest - nearest);
  }

  /// How much farther the pixel is than the mean of its neighbours `radius` px away on one axis
  /// (> 0 in a concave corner, <= 0 on a plane or a convex edge); 0 where a neighbour is missing.
  static float concavity(const cv::Mat& ideal, int u, int v, int radius) {
    const float z = ideal.at<float>(v, u);
    float deepest = 0.0f;
    if (u >= radius && u + radius < ideal.cols) {
      const float left = ideal.at<float>(v, u - radius);
      const float right = ideal.at<float>(v, u + radius);
      if (hasDepth(left) && hasDepth(right)) deepest = std::max(deepest, z - 0.5f * (left + right));
    }
    if (v >= radius && v + radius < ideal.rows) {
      const float up = ideal.at<float>(v - radius, u);
      const float down = ideal.at<float>(v + radius, u);
      if (hasDepth(up) && hasDepth(down)) deepest = std::max(deepest, z - 0.5f * (up + down));
    }
    // A step in depth is an edge, not a corner: cap at a tenth of the depth.
    return std::min(deepest, 0.1f * z);
  }

  AzureKinectParameters p_;
  Quantiser quantised_;
};

}  // namespace

namespace {

/// One pixel's depth and its four neighbours (the pixel itself beyond the border), with the
/// rays' slopes there: what DepthGeometry needs of it.
struct Neighbourhood {
  float z, left, right, above, below;
  float ray_left, ray_centre_x, ray_right;   // (u - cx) / fx at u - 1, u, u + 1 (clamped)
  float ray_above, ray_centre_y, ray_below;  // (v - cy) / fy at v - 1, v, v + 1 (clamped)
};

/// |cos| of the incidence angle (1 at an edge or without depth) and whether the pixel is an edge.
/// Branch-free, so that the loop over a row's interior vectorises.
inline void geometryAt(const Neighbourhood& n, float slope, float& cos_out,
                       std::uint8_t& edge_out) {
  // Bitwise, not short-circuit, logic and unconditional arithmetic (NaN where there is no depth,
  // then not selected): no branch in the loop.
  const auto near = [&](float other) {
    return hasDepth(other) & (std::abs(other - n.z) <= slope * std::min(other, n.z));
  };
  const bool surface = hasDepth(n.z);
  const bool smooth = near(n.left) & near(n.right) & near(n.above) & near(n.below);
  // Normal = (dP/du) x (dP/dv) of the back-projected points P = z (a_u, b_v, 1).
  const float du[3] = {n.right * n.ray_right - n.left * n.ray_left,
                       (n.right - n.left) * n.ray_centre_y, n.right - n.left};
  const float dv[3] = {(n.below - n.above) * n.ray_centre_x,
                       n.below * n.ray_below - n.above * n.ray_above, n.below - n.above};
  const float normal[3] = {du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2],
                           du[0] * dv[1] - du[1] * dv[0]};
  const float dot = normal[0] * n.ray_centre_x + normal[1] * n.ray_centre_y + normal[2];
  const float norms_sq = (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]) *
                         (n.ray_centre_x * n.ray_centre_x + n.ray_centre_y * n.ray_centre_y + 1.0f);
  const float cos_incidence = std::abs(dot) / std::sqrt(norms_sq);
  const bool measured = surface & smooth & (norms_sq > 0.0f);
  cos_out = measured ? cos_incidence : 1.0f;
  edge_out = static_cast<std::uint8_t>(surface & !smooth);
}

}  // namespace

void DepthGeometry::compute(const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                            const EdgeParameters& edge_parameters) {
  cos_incidence.create(depth.size(), CV_32FC1);
  edge.create(depth.size(), CV_8UC1);
  const float slope = static_cast<float>(edge_parameters.max_slope / intrinsics.fx);
  const int w = depth.cols;
  const int h = depth.rows;
  ray_x_.resize(w);
  ray_y_.resize(h);
  for (int u = 0; u < w; ++u) ray_x_[u] = static_cast<float>((u - intrinsics.cx) / intrinsics.fx);
  for (int v = 0; v < h; ++v) ray_y_[v] = static_cast<float>((v - intrinsics.cy) / intrinsics.fy);
  for (int v = 0; v < h; ++v) {
    const int up = std::max(v - 1, 0), down = std::min(v + 1, h - 1);
    const float* z = depth.ptr<float>(v);
    const float* above = depth.ptr<float>(up);
    const float* below = depth.ptr<float>(down);
    float* cos_out = cos_incidence.ptr<float>(v);
    std::uint8_t* edge_out = edge.ptr<std::uint8_t>(v);
    const float* rx = ray_x_.data();
    const float ray_above = ray_y_[up], ray_centre = ray_y_[v], ray_below = ray_y_[down];
    const auto at = [=](int u, int left, int right) {
      return Neighbourhood{z[u],  z[left],   z[right],  above[u],   below[u], rx[left],
                           rx[u], rx[right], ray_above, ray_centre, ray_below};
    };
    geometryAt(at(0, 0, std::min(1, w - 1)), slope, cos_out[0], edge_out[0]);
    for (int u = 1; u + 1 < w; ++u) geometryAt(at(u, u - 1, u + 1), slope, cos_out[u], edge_out[u]);
    if (w > 1) geometryAt(at(w - 1, w - 2, w - 1), slope, cos_out[w - 1], edge_out[w - 1]);
  }
}

const std::vector<std::string>& depthSensorNames() {
  static const std::vector<std::string> names = {"ideal", "kinect_v1", "realsense_d435",
                                                 "azure_kinect"};
  return names;
}

std::unique_ptr<DepthSensorModel> makeDepthSensorModel(const std::string& name,
                                                       const SensorParameters& parameters) {
  if (name == "kinect_v1") return std::make_unique<KinectV1Model>(parameters.kinect_v1);
  if (name == "realsense_d435") {
    return std::make_unique<RealSenseD435Model>(parameters.realsense_d435);
  }
  if (name == "azure_kinect") return std::make_unique<AzureKinectModel>(parameters.azure_kinect);
  if (name == "ideal") return nullptr;
  throw InvalidArgumentError(
      "option 'depth_sensor' must be one of ideal, kinect_v1, "
      "realsense_d435, azure_kinect, got " +
      quoted(name));
}

}  // namespace occlusion_env
