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

float quantised(float z, double step_m) {
  if (step_m <= 0.0) return z;
  return static_cast<float>(std::round(z / step_m) * step_m);
}

double incidenceAngle(float cos_incidence) {
  return std::min(std::acos(std::clamp(static_cast<double>(cos_incidence), 0.0, 1.0)),
                  kMaxIncidenceRad);
}

/// Marks in `shadow` (CV_8UC1, 1 = hidden) the pixels that a second viewpoint `baseline_m` along
/// +x (a projector or the right imager) cannot see, from the ideal depth: scanning each row from
/// the right, a pixel whose column in the other view lies beyond the nearest one seen so far is
/// behind a nearer surface there. Also marks what falls left of the other view's image.
void markHiddenFromSecondView(const cv::Mat& depth, double fx, double baseline_m,
                              bool outside_is_hidden, cv::Mat& shadow) {
  shadow.create(depth.size(), CV_8UC1);
  const float shift = static_cast<float>(fx * baseline_m);
  for (int v = 0; v < depth.rows; ++v) {
    const float* z = depth.ptr<float>(v);
    std::uint8_t* hidden = shadow.ptr<std::uint8_t>(v);
    float nearest_column = std::numeric_limits<float>::infinity();
    for (int u = depth.cols - 1; u >= 0; --u) {
      hidden[u] = 0;
      if (!hasDepth(z[u])) continue;
      const float column = static_cast<float>(u) - shift / z[u];
      if (column > nearest_column || (outside_is_hidden && column < 0.0f)) {
        hidden[u] = 1;
      } else {
        nearest_column = column;
      }
    }
  }
}

/// `band` = `mask` dilated by a (2r + 1)^2 square; `scratch` holds the horizontal pass.
void dilateSquare(const cv::Mat& mask, int radius, cv::Mat& scratch, cv::Mat& band) {
  scratch.create(mask.size(), CV_8UC1);
  band.create(mask.size(), CV_8UC1);
  const int w = mask.cols;
  const int h = mask.rows;
  for (int v = 0; v < h; ++v) {
    const std::uint8_t* in = mask.ptr<std::uint8_t>(v);
    std::uint8_t* out = scratch.ptr<std::uint8_t>(v);
    int last_set = -1 - 2 * radius - 1;  // column of the last set pixel at or left of u + radius
    for (int u = 0; u < w + radius; ++u) {
      if (u < w && in[u]) last_set = u;
      const int centre = u - radius;
      if (centre >= 0) out[centre] = (last_set >= centre - radius) ? 1 : 0;
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
  explicit KinectV1Model(const KinectV1Parameters& p) : p_(p) {}
  std::string name() const override { return "kinect_v1"; }

  void measure(const cv::Mat& ideal, const cv::Mat& /*rgb*/, const CameraIntrinsics& intrinsics,
               const DepthGeometry& geometry, RandomSource& random, cv::Mat& measured) override {
    measured.create(ideal.size(), CV_32FC1);
    const double pixel_scale = intrinsics.fx / p_.focal_length_px;  // sensor px -> rendered px
    const int w = ideal.cols;
    const int h = ideal.rows;
    for (int v = 0; v < h; ++v) {
      float* out = measured.ptr<float>(v);
      for (int u = 0; u < w; ++u) {
        // Lateral noise: the reading comes from a jittered point of the surface.
        const double theta = incidenceAngle(geometry.cos_incidence.at<float>(v, u));
        const double grazing = theta / (0.5 * M_PI - theta);
        const double sigma_lateral =
            (p_.lateral_constant_px + p_.lateral_grazing_px * grazing) * pixel_scale;
        const int su = std::clamp(
            u + static_cast<int>(std::lround(sigma_lateral * fastStandardNormal(random))), 0,
            w - 1);
        const int sv = std::clamp(
            v + static_cast<int>(std::lround(sigma_lateral * fastStandardNormal(random))), 0,
            h - 1);
        out[u] = axialReading(ideal.at<float>(sv, su), grazing, random);
      }
    }
    // The projector's shadow: no pattern, no depth.
    markHiddenFromSecondView(ideal, intrinsics.fx, p_.projector_baseline_m, false, shadow_);
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
  float axialReading(float z, double grazing, RandomSource& random) const {
    if (!hasDepth(z) || z < p_.min_range_m || z > p_.max_range_m) return kNaN;
    const float noisy = z + static_cast<float>(axialSigma(z, grazing)) * fastStandardNormal(random);
    if (p_.hole_rate > 0.0 && random.uniform() < p_.hole_rate) return kNaN;
    return quantised(noisy, p_.quantisation_m);
  }

  KinectV1Parameters p_;
  cv::Mat shadow_;
};

class RealSenseD435Model : public DepthSensorModel {
 public:
  explicit RealSenseD435Model(const RealSenseD435Parameters& p) : p_(p) {}
  std::string name() const override { return "realsense_d435"; }

  void measure(const cv::Mat& ideal, const cv::Mat& rgb, const CameraIntrinsics& intrinsics,
               const DepthGeometry& geometry, RandomSource& random, cv::Mat& measured) override {
    measured.create(ideal.size(), CV_32FC1);
    const int band_radius = std::max(
        1, static_cast<int>(std::lround(p_.edge_band_px * intrinsics.fx / p_.focal_length_px)));
    dilateSquare(geometry.edge, band_radius, scratch_, edge_band_);
    // The right imager's view: occluded there or outside its image (the left band) = no match.
    markHiddenFromSecondView(ideal, intrinsics.fx, p_.baseline_m, true, hidden_);
    const float cos_grazing = static_cast<float>(std::cos(p_.grazing_angle_rad));
    const bool read_rgb = !rgb.empty() && rgb.size() == ideal.size();
    for (int v = 0; v < ideal.rows; ++v) {
      const float* z = ideal.ptr<float>(v);
      const std::uint8_t* band = edge_band_.ptr<std::uint8_t>(v);
      const std::uint8_t* hidden = hidden_.ptr<std::uint8_t>(v);
      const float* cos_incidence = geometry.cos_incidence.ptr<float>(v);
      const cv::Vec3b* colour = read_rgb ? rgb.ptr<cv::Vec3b>(v) : nullptr;
      float* out = measured.ptr<float>(v);
      for (int u = 0; u < ideal.cols; ++u) {
        out[u] = kNaN;
        if (!hasDepth(z[u]) || hidden[u] || z[u] < p_.min_range_m || z[u] > p_.max_range_m) {
          continue;
        }
        double dropout = p_.hole_rate;
        if (band[u]) dropout = std::max(dropout, p_.edge_dropout_probability);
        if (cos_incidence[u] < cos_grazing) {
          dropout = std::max(dropout, p_.grazing_dropout_probability);
        }
        if (colour && luminance(colour[u]) < p_.dark_luminance) {
          dropout = std::max(dropout, p_.dark_dropout_probability);
        }
        const float noise = fastStandardNormal(random);
        if (dropout > 0.0 && random.uniform() < dropout) continue;
        out[u] = quantised(disparityReading(z[u], noise), p_.quantisation_m);
      }
    }
  }

 private:
  /// Depth from a disparity (in the sensor's pixels) with noise sigma_d: z = f B / (d + e).
  float disparityReading(float z, float standard_normal) const {
    const double f_b = p_.focal_length_px * p_.baseline_m;
    const double disparity = f_b / z + p_.disparity_sigma_px * standard_normal;
    return static_cast<float>(f_b / disparity);
  }

  static double luminance(const cv::Vec3b& rgb) {
    return (0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]) / 255.0;
  }

  RealSenseD435Parameters p_;
  cv::Mat scratch_;
  cv::Mat edge_band_;
  cv::Mat hidden_;
};

class AzureKinectModel : public DepthSensorModel {
 public:
  explicit AzureKinectModel(const AzureKinectParameters& p) : p_(p) {}
  std::string name() const override { return "azure_kinect"; }

  void measure(const cv::Mat& ideal, const cv::Mat& /*rgb*/, const CameraIntrinsics& intrinsics,
               const DepthGeometry& geometry, RandomSource& random, cv::Mat& measured) override {
    measured.create(ideal.size(), CV_32FC1);
    const int radius = std::max(
        1,
        static_cast<int>(std::lround(p_.multipath_radius_px * intrinsics.fx / p_.focal_length_px)));
    for (int v = 0; v < ideal.rows; ++v) {
      const float* z = ideal.ptr<float>(v);
      const std::uint8_t* edge = geometry.edge.ptr<std::uint8_t>(v);
      float* out = measured.ptr<float>(v);
      for (int u = 0; u < ideal.cols; ++u) {
        out[u] = kNaN;
        if (!hasDepth(z[u])) continue;
        float reading = z[u];
        if (edge[u]) {
          // A pixel that straddles an edge integrates both surfaces.
          const double draw = random.uniform();
          if (draw >= p_.flying_pixel_probability + p_.edge_invalid_probability) {
            // kept as it is
          } else if (draw >= p_.flying_pixel_probability) {
            continue;
          } else {
            reading = flyingPixel(ideal, u, v, random);
          }
        } else {
          reading += static_cast<float>(p_.multipath_gain * concavity(ideal, u, v, radius));
        }
        if (reading < p_.min_range_m || reading > p_.max_range_m) continue;
        reading += static_cast<float>(axialSigma(reading)) * fastStandardNormal(random);
        if (p_.hole_rate > 0.0 && random.uniform() < p_.hole_rate) continue;
        out[u] = quantised(reading, p_.quantisation_m);
      }
    }
  }

  double axialSigma(double z) const { return p_.axial_constant_m + p_.axial_linear * z; }

 private:
  /// A depth between the nearest and farthest surface of the 3x3 neighbourhood (NaN = ignored).
  static float flyingPixel(const cv::Mat& ideal, int u, int v, RandomSource& random) {
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
    const float mix = static_cast<float>(random.uniform());
    return nearest + mix * (farthest - nearest);
  }

  /// How much farther the pixel is than the mean of its neighbours `radius` px away on one axis
  /// (> 0 in a concave corner, <= 0 on a plane or a convex edge); 0 where a neighbour is missing.
  static double concavity(const cv::Mat& ideal, int u, int v, int radius) {
    const float z = ideal.at<float>(v, u);
    double deepest = 0.0;
    if (u >= radius && u + radius < ideal.cols) {
      const float left = ideal.at<float>(v, u - radius);
      const float right = ideal.at<float>(v, u + radius);
      if (hasDepth(left) && hasDepth(right)) deepest = std::max(deepest, z - 0.5 * (left + right));
    }
    if (v >= radius && v + radius < ideal.rows) {
      const float up = ideal.at<float>(v - radius, u);
      const float down = ideal.at<float>(v + radius, u);
      if (hasDepth(up) && hasDepth(down)) deepest = std::max(deepest, z - 0.5 * (up + down));
    }
    // A step in depth is an edge, not a corner: cap at a tenth of the depth.
    return std::min(deepest, 0.1 * z);
  }

  AzureKinectParameters p_;
};

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
    const float* z = depth.ptr<float>(v);
    const float* above = depth.ptr<float>(std::max(v - 1, 0));
    const float* below = depth.ptr<float>(std::min(v + 1, h - 1));
    float* cos_out = cos_incidence.ptr<float>(v);
    std::uint8_t* edge_out = edge.ptr<std::uint8_t>(v);
    for (int u = 0; u < w; ++u) {
      cos_out[u] = 1.0f;
      edge_out[u] = 0;
      if (!hasDepth(z[u])) continue;
      const float left = z[std::max(u - 1, 0)];
      const float right = z[std::min(u + 1, w - 1)];
      const float neighbours[4] = {left, right, above[u], below[u]};
      bool smooth = true;
      for (float n : neighbours) {
        if (!hasDepth(n) || std::abs(n - z[u]) > slope * std::min(n, z[u])) smooth = false;
      }
      if (!smooth) {
        edge_out[u] = 1;
        continue;
      }
      // Normal = (dP/du) x (dP/dv) of the back-projected points P = z (a_u, b_v, 1).
      const int ul = std::max(u - 1, 0), ur = std::min(u + 1, w - 1);
      const float du[3] = {right * ray_x_[ur] - left * ray_x_[ul], (right - left) * ray_y_[v],
                           right - left};
      const float dv[3] = {
          (below[u] - above[u]) * ray_x_[u],
          below[u] * ray_y_[std::min(v + 1, h - 1)] - above[u] * ray_y_[std::max(v - 1, 0)],
          below[u] - above[u]};
      const float normal[3] = {du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2],
                               du[0] * dv[1] - du[1] * dv[0]};
      const float ray[3] = {ray_x_[u], ray_y_[v], 1.0f};
      const float dot = normal[0] * ray[0] + normal[1] * ray[1] + normal[2];
      const float norms =
          std::sqrt((normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]) *
                    (ray[0] * ray[0] + ray[1] * ray[1] + 1.0f));
      if (norms > 0.0f) cos_out[u] = std::abs(dot) / norms;
    }
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
