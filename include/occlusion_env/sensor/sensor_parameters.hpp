// Parameters of the simulated camera's sensor models, with the values config/sensors.yaml ships
// (doc/SENSORS.md cites where each comes from). Lengths in metres, angles in radians, image
// distances in pixels of the modelled sensor's own depth image (its `focal_length_px`), which the
// models convert to the rendered image's pixels.
#pragma once

#include <string>

namespace occlusion_env {

/// Structured light (Kinect v1): Nguyen, Izadi & Lovell 2012 for the noise; the projector beside
/// the IR camera casts a shadow band with no depth beside foreground edges.
struct KinectV1Parameters {
  double axial_constant_m = 0.0012;       // sigma_z = c + q (z - z0)^2 + grazing term
  double axial_quadratic_m = 0.0019;      // [m per m^2]
  double axial_offset_m = 0.4;            // z0
  double grazing_coefficient_m = 0.0001;  // * theta^2 / sqrt(z) / (pi/2 - theta)^2
  double lateral_constant_px = 0.8;       // sigma_L = a + b theta / (pi/2 - theta)
  double lateral_grazing_px = 0.035;
  double focal_length_px = 580.0;       // IR camera at 640x480
  double projector_baseline_m = 0.075;  // projector on the +x side of the IR camera
  double quantisation_m = 0.001;        // depth step
  double min_range_m = 0.4;
  double max_range_m = 5.0;
  double hole_rate = 0.0;  // random invalid pixels anywhere (fraction)
};

/// Active stereo (RealSense D435): disparity noise gives z^2 sigma_d / (f B); the left imager's
/// border that the right one does not see; matching fails at edges, on dark and grazing surfaces.
struct RealSenseD435Parameters {
  double disparity_sigma_px = 0.08;  // subpixel RMS
  double focal_length_px = 430.0;    // depth imagers at 848x480 (~87 deg)
  double baseline_m = 0.050;         // right imager on the +x side of the left (reference) one
  double quantisation_m = 0.001;     // depth unit
  double min_range_m = 0.28;
  double max_range_m = 10.0;
  double edge_band_px = 2.0;  // dropout this far either side of a depth discontinuity
  double edge_dropout_probability = 0.7;
  double dark_luminance = 0.08;  // [0, 1] rgb luminance below which matching often fails
  double dark_dropout_probability = 0.5;
  double grazing_angle_rad = 1.309;  // 75 deg between surface normal and viewing ray
  double grazing_dropout_probability = 0.8;
  double hole_rate = 0.002;
};

/// Time of flight (Azure Kinect, NFOV 2x2 binned): small axial noise, flying pixels (foreground
/// and background mixed, or invalidated) at edges, multipath bias in concave corners.
struct AzureKinectParameters {
  double axial_constant_m = 0.0008;  // sigma_z = c + k z
  double axial_linear = 0.0008;      // [m per m]
  double focal_length_px = 209.0;    // 320x288 binned NFOV (75 x 65 deg)
  double quantisation_m = 0.001;
  double min_range_m = 0.5;
  double max_range_m = 5.46;
  double flying_pixel_probability = 0.5;  // at an edge: mixed depth; otherwise invalidated
  double edge_invalid_probability = 0.3;
  double multipath_gain = 0.5;  // bias = gain * max(0, z - local mean of z)
  double multipath_radius_px = 4.0;
  double hole_rate = 0.001;
};

/// Photometric effects of a real colour camera, drawn per scene (exposure, white balance) and per
/// pixel (noise).
struct RgbEffectParameters {
  double exposure_log2_range = 0.5;   // gain = 2^U(-r, r)
  double white_balance_range = 0.08;  // per-channel gain in 1 +/- r
  double read_noise = 2.0;            // [DN] sigma of the noise floor
  double shot_noise = 0.03;           // [DN] sigma^2 grows by this per DN of signal
  double blur_sigma_px = 0.6;         // Gaussian blur of the optics, in rendered pixels
  int jpeg_quality = 0;               // 0: no JPEG round trip; else 1..100
};

/// Discontinuity test shared by the models: neighbours differ by more than this many pixel
/// footprints (a surface steeper than atan(max_slope) towards the camera is an edge).
struct EdgeParameters {
  double max_slope = 6.0;
};

struct SensorParameters {
  KinectV1Parameters kinect_v1;
  RealSenseD435Parameters realsense_d435;
  AzureKinectParameters azure_kinect;
  RgbEffectParameters rgb;
  EdgeParameters edge;
};

/// Reads config/sensors.yaml's layout; keys left out keep the defaults above. Throws
/// InvalidArgumentError for an unreadable file, an unknown key or a value out of range.
SensorParameters loadSensorParameters(const std::string& path);

/// Throws InvalidArgumentError naming the first parameter out of range.
void validate(const SensorParameters& parameters);

}  // namespace occlusion_env
