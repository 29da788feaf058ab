// config/sensors.yaml: one map per model, keys as the members of sensor_parameters.hpp.
#include "occlusion_env/sensor/sensor_parameters.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
#include <sstream>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

/// A model's keys and where each value goes.
using DoubleFields = std::map<std::string, double*>;

void readSection(const YAML::Node& root, const std::string& section, const DoubleFields& fields,
                 const std::string& path) {
  const YAML::Node node = root[section];
  if (!node) return;
  if (!node.IsMap()) throw InvalidArgumentError(path + ": '" + section + "' is not a map");
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    const auto field = fields.find(key);
    if (field == fields.end()) {
      throw InvalidArgumentError(path + ": unknown key '" + section + "." + key + "'");
    }
    try {
      *field->second = entry.second.as<double>();
    } catch (const YAML::Exception&) {
      throw InvalidArgumentError(path + ": '" + section + "." + key + "' is not a number");
    }
  }
}

void requireRange(double value, double lo, double hi, const std::string& name) {
  if (std::isfinite(value) && value >= lo && value <= hi) return;
  std::ostringstream message;
  message << "sensor parameter '" << name << "' must be in [" << lo << ", " << hi << "], got "
          << value;
  throw InvalidArgumentError(message.str());
}

}  // namespace

SensorParameters loadSensorParameters(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& error) {
    throw InvalidArgumentError("sensor parameters " + path + ": " + error.what());
  }
  if (!root.IsMap()) throw InvalidArgumentError("sensor parameters " + path + ": not a YAML map");
  for (const auto& entry : root) {
    const std::string key = entry.first.as<std::string>();
    if (key != "kinect_v1" && key != "realsense_d435" && key != "azure_kinect" && key != "rgb" &&
        key != "edge") {
      throw InvalidArgumentError(path + ": unknown section '" + key + "'");
    }
  }
  SensorParameters p;
  KinectV1Parameters& k = p.kinect_v1;
  readSection(root, "kinect_v1",
              {{"axial_constant_m", &k.axial_constant_m},
               {"axial_quadratic_m", &k.axial_quadratic_m},
               {"axial_offset_m", &k.axial_offset_m},
               {"grazing_coefficient_m", &k.grazing_coefficient_m},
               {"lateral_constant_px", &k.lateral_constant_px},
               {"lateral_grazing_px", &k.lateral_grazing_px},
               {"focal_length_px", &k.focal_length_px},
               {"projector_baseline_m", &k.projector_baseline_m},
               {"quantisation_m", &k.quantisation_m},
               {"min_range_m", &k.min_range_m},
               {"max_range_m", &k.max_range_m},
               {"hole_rate", &k.hole_rate}},
              path);
  RealSenseD435Parameters& r = p.realsense_d435;
  readSection(root, "realsense_d435",
              {{"disparity_sigma_px", &r.disparity_sigma_px},
               {"focal_length_px", &r.focal_length_px},
               {"baseline_m", &r.baseline_m},
               {"quantisation_m", &r.quantisation_m},
               {"min_range_m", &r.min_range_m},
               {"max_range_m", &r.max_range_m},
               {"edge_band_px", &r.edge_band_px},
               {"edge_dropout_probability", &r.edge_dropout_probability},
               {"dark_luminance", &r.dark_luminance},
               {"dark_dropout_probability", &r.dark_dropout_probability},
               {"grazing_angle_rad", &r.grazing_angle_rad},
               {"grazing_dropout_probability", &r.grazing_dropout_probability},
               {"hole_rate", &r.hole_rate}},
              path);
  AzureKinectParameters& a = p.azure_kinect;
  readSection(root, "azure_kinect",
              {{"axial_constant_m", &a.axial_constant_m},
               {"axial_linear", &a.axial_linear},
               {"focal_length_px", &a.focal_length_px},
               {"quantisation_m", &a.quantisation_m},
               {"min_range_m", &a.min_range_m},
               {"max_range_m", &a.max_range_m},
               {"flying_pixel_probability", &a.flying_pixel_probability},
               {"edge_invalid_probability", &a.edge_invalid_probability},
               {"multipath_gain", &a.multipath_gain},
               {"multipath_radius_px", &a.multipath_radius_px},
               {"hole_rate", &a.hole_rate}},
              path);
  double jpeg_quality = p.rgb.jpeg_quality;
  readSection(root, "rgb",
              {{"exposure_log2_range", &p.rgb.exposure_log2_range},
               {"white_balance_range", &p.rgb.white_balance_range},
               {"read_noise", &p.rgb.read_noise},
               {"shot_noise", &p.rgb.shot_noise},
               {"blur_sigma_px", &p.rgb.blur_sigma_px},
               {"jpeg_quality", &jpeg_quality}},
              path);
  requireRange(jpeg_quality, 0, 100, "rgb.jpeg_quality");
  p.rgb.jpeg_quality = static_cast<int>(jpeg_quality);
  readSection(root, "edge", {{"max_slope", &p.edge.max_slope}}, path);
  validate(p);
  return p;
}

void validate(const SensorParameters& p) {
  const auto probability = [](double value, const std::string& name) {
    requireRange(value, 0.0, 1.0, name);
  };
  const auto ranges = [](double lo, double hi, const std::string& model) {
    requireRange(lo, 0.0, 100.0, model + ".min_range_m");
    requireRange(hi, lo, 100.0, model + ".max_range_m");
  };
  const KinectV1Parameters& k = p.kinect_v1;
  requireRange(k.focal_length_px, 1.0, 1e5, "kinect_v1.focal_length_px");
  requireRange(k.projector_baseline_m, 0.0, 1.0, "kinect_v1.projector_baseline_m");
  requireRange(k.quantisation_m, 0.0, 0.1, "kinect_v1.quantisation_m");
  ranges(k.min_range_m, k.max_range_m, "kinect_v1");
  probability(k.hole_rate, "kinect_v1.hole_rate");
  const RealSenseD435Parameters& r = p.realsense_d435;
  requireRange(r.focal_length_px, 1.0, 1e5, "realsense_d435.focal_length_px");
  requireRange(r.baseline_m, 1e-3, 1.0, "realsense_d435.baseline_m");
  requireRange(r.disparity_sigma_px, 0.0, 10.0, "realsense_d435.disparity_sigma_px");
  requireRange(r.quantisation_m, 0.0, 0.1, "realsense_d435.quantisation_m");
  ranges(std::max(r.min_range_m, 1e-3), r.max_range_m, "realsense_d435");
  requireRange(r.edge_band_px, 0.0, 64.0, "realsense_d435.edge_band_px");
  probability(r.edge_dropout_probability, "realsense_d435.edge_dropout_probability");
  probability(r.dark_luminance, "realsense_d435.dark_luminance");
  probability(r.dark_dropout_probability, "realsense_d435.dark_dropout_probability");
  requireRange(r.grazing_angle_rad, 0.0, 0.5 * M_PI, "realsense_d435.grazing_angle_rad");
  probability(r.grazing_dropout_probability, "realsense_d435.grazing_dropout_probability");
  probability(r.hole_rate, "realsense_d435.hole_rate");
  const AzureKinectParameters& a = p.azure_kinect;
  requireRange(a.focal_length_px, 1.0, 1e5, "azure_kinect.focal_length_px");
  requireRange(a.quantisation_m, 0.0, 0.1, "azure_kinect.quantisation_m");
  ranges(a.min_range_m, a.max_range_m, "azure_kinect");
  probability(a.flying_pixel_probability, "azure_kinect.flying_pixel_probability");
  requireRange(a.edge_invalid_probability, 0.0, 1.0 - a.flying_pixel_probability,
               "azure_kinect.edge_invalid_probability");
  requireRange(a.multipath_gain, 0.0, 10.0, "azure_kinect.multipath_gain");
  requireRange(a.multipath_radius_px, 1.0, 64.0, "azure_kinect.multipath_radius_px");
  probability(a.hole_rate, "azure_kinect.hole_rate");
  requireRange(p.rgb.exposure_log2_range, 0.0, 4.0, "rgb.exposure_log2_range");
  requireRange(p.rgb.white_balance_range, 0.0, 0.9, "rgb.white_balance_range");
  requireRange(p.rgb.read_noise, 0.0, 64.0, "rgb.read_noise");
  requireRange(p.rgb.shot_noise, 0.0, 10.0, "rgb.shot_noise");
  requireRange(p.rgb.blur_sigma_px, 0.0, 10.0, "rgb.blur_sigma_px");
  requireRange(p.rgb.jpeg_quality, 0, 100, "rgb.jpeg_quality");
  requireRange(p.edge.max_slope, 0.5, 1000.0, "edge.max_slope");
}

}  // namespace occlusion_env
