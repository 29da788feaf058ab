// What the networks see, written down once: an RGB-D observation resized to the network's
// resolution and normalised, as a C x S x S float tensor (C = InputFormat::channels(): 4 or 5).
//
//   channels 0-2: RGB / 255, then (x - 0.5) / 0.25
//   channel 3:    depth [m] clamped to [0, kFarDepthM] / kFarDepthM, then (x - 0.5) / 0.25
//   channel 4:    only with a model's depth_validity: channel: the fraction of the network
//                 pixel's area with a depth reading (0-1), then (x - 0.5) / 0.25; so that a
//                 filled input still shows where a sensor lost its readings (an edge band)
// Resizing: area averaging (cv::INTER_AREA). Missing depth (NaN: nothing hit, or a sensor's
// dropout) enters as the model's DepthGaps says:
//   far:    every missing pixel is far (kFarDepthM) before averaging, so a pixel at an object's
//           edge blends object and far background (the models trained in the void, before
//           depth-sensor models existed);
//   filled: averaged over the valid pixels only; a network pixel with none takes the mean of its
//           valid 8-neighbours when at least 4 of them are valid (a sensor's speckle and edge
//           dropouts), else it is far (the void, large holes). A real depth camera's dropouts
//           then look like the surface around them, not like holes to the background.
// Floors and walls (a model's bounding_surfaces):
//   kept:    the view as it is;
//   cleared: the network pixels on the view's bounding surfaces (large planes with nothing seen
//            behind them: occlusion/bounding_surfaces.hpp, found in the network pixels' mean
//            depth as the network reads it, relative to the radius where the model's depth is,
//            with clearedInputSurfaceOptions()) enter as the void, black and far, so that
//            a network trained on objects in the void sees a room as the void around its
//            objects; so do the network pixels with no depth reading at all (a wall beyond the
//            sensor's range), as the void's background has none. Needs the camera's intrinsics.
// Depth (a model's depth_reference):
//   metres: as the camera reads it;
//   radius: times kWorkingRadiusM / r, r the camera's distance from the sphere's centre, so that
//           a scene scaled with its sphere (small objects seen from 1 m) enters as the same
//           scene at 4 m would, each reading clamped at far in that depth before a block is
//           averaged; the void's far stays far. Needs r (InputFormat::atRadius).
// Crop (a model's view_crop):
//   1:       the whole view;
//   c < 1:   the centred c x c of the view's width and height only (viewCropRect), the
//            intrinsics moved with it, at the network's size: a finer look at the middle of the
//            view, where the objects at the sphere's centre are (99.7 % of the occluded pixels of
//            the bridge's roll-outs lie in the central half). The labels are cropped alike.
#pragma once

#include <memory>
#include <opencv2/core.hpp>

#include "occlusion_env/geometry/camera.hpp"
#include "occlusion_env/occlusion/bounding_surfaces.hpp"

namespace occlusion_env {
namespace learning {

constexpr double kFarDepthM = 8.0;       // beyond the sphere (r = 4 m) and every object
constexpr double kWorkingRadiusM = 4.0;  // the sphere's radius the networks were trained at

/// How a value in [0, 1] enters the network, in every channel.
constexpr float normalisedInput(float unit) {
  return (unit - 0.5f) / 0.25f;
}
/// The void's input values: black RGB, no depth (read as far) and, in a valid-fraction channel,
/// nothing read. Cleared surfaces, shifted borders and dropped depth all enter as these.
constexpr float kBlackInput = normalisedInput(0.0f);
constexpr float kNoDepthInput = normalisedInput(1.0f);
constexpr float kNothingReadInput = normalisedInput(0.0f);

enum class DepthGaps { kFar, kFilled };

/// The network's input: its size, how missing depth enters and whether floors and walls do
/// (NetworkConfig::inputFormat()).
struct InputFormat {
  // From a size alone (implicitly): the input of the models before DepthGaps existed.
  InputFormat(int size_px = 64, DepthGaps gaps = DepthGaps::kFar,  // NOLINT(runtime/explicit)
              bool clear_surfaces = false, bool per_radius = false)
      : size(size_px),
        depth_gaps(gaps),
        clear_bounding_surfaces(clear_surfaces),
        depth_per_radius(per_radius) {}
  int size;  // [px], width and height
  DepthGaps depth_gaps;
  bool clear_bounding_surfaces;  // the view's floors and walls enter as the void
  bool depth_per_radius;         // depth enters relative to the camera's radius (radius_m)
  double radius_m = 0.0;         // [m] the camera's distance from the sphere's centre; 0: unknown
  double view_crop = 1.0;        // the centred fraction of the view's width and height it sees
  double view_field_of_view = 0.0;      // [rad] the angle of view it sees; 0: as view_crop says
  bool valid_fraction_channel = false;  // a fifth channel: each pixel's share of depth readings

  /// The input's channels: RGB and depth, and the valid fraction when it has that channel.
  int channels() const { return valid_fraction_channel ? 5 : 4; }
  /// Whether writeNetworkInput leaves sumValidDepth's sums of the view in its scratch (the
  /// filled depth and the valid-fraction channel are made from them), so that a caller needing
  /// them need not sum again.
  bool sumsValidDepth() const { return depth_gaps == DepthGaps::kFilled || valid_fraction_channel; }
  /// Whether the network sees a part of the view only (view_crop or view_field_of_view).
  bool cropsView() const { return view_crop != 1.0 || view_field_of_view > 0.0; }

  /// This format for a view from `camera_radius_m` [m] (used only when depth_per_radius).
  InputFormat atRadius(double camera_radius_m) const;
  /// What depth [m] is multiplied by before it is normalised: 1, or kWorkingRadiusM / radius_m
  /// when depth_per_radius. Throws InvalidArgumentError when that needs a radius and has none.
  double depthScale() const;
  /// The reading [m] the network reads as far, kFarDepthM / depthScale(): each reading is clamped
  /// there before a network pixel's block is averaged, so a block reads as at 4 m.
  float farReadingM() const {
    return static_cast<float>(kFarDepthM) / static_cast<float>(depthScale());
  }
};

/// The camera's distance from the sphere's centre [m]: the optical frame's origin in the sphere
/// (world) frame; 0 for the identity a caller without a pose gives.
inline double cameraRadius(const Eigen::Isometry3d& sphere_from_optical) {
  return sphere_from_optical.translation().norm();
}

/// The centred part of an image of `image_size` a network with `view_crop` sees: `view_crop`
/// of its width and height (at least 1 px each), the whole image at 1.
cv::Rect viewCropRect(const cv::Size& image_size, double view_crop);

/// The part of an image of `image_size`, seen with `intrinsics`, that a network in `format` sees:
/// with a view_field_of_view, the square of that angle around the principal point (fx and fy
/// times its half-angle's tangent either side, rounded to whole pixels), which may reach beyond
/// the image; else viewCropRect. Throws InvalidArgumentError for a view_field_of_view outside
/// (0, pi) or intrinsics without focal lengths when it needs them.
cv::Rect seenViewRect(const cv::Size& image_size, const CameraIntrinsics& intrinsics,
                      const InputFormat& format);

/// `image`'s part `rect`: a view into it (no copy) when `rect` lies inside it, else a copy into
/// `padded` (sized once) with `fill` where `rect` reaches beyond it.
cv::Mat viewPart(const cv::Mat& image, const cv::Rect& rect, const cv::Scalar& fill,
                 cv::Mat& padded);

/// `intrinsics` of a whole image, for its part `crop`.
CameraIntrinsics croppedIntrinsics(const CameraIntrinsics& intrinsics, const cv::Rect& crop);

/// The resized images between calls (no allocation once sized).
struct InputScratch {
  cv::Mat rgb_padded, depth_padded;  // a view's part where it reaches beyond the image
  cv::Mat depth_filled, valid, rgb_small, depth_small, valid_small;
  cv::Mat grid_depth, on_surface;  // size x size: mean depth [m] (scaled), 255 on a surface
  std::unique_ptr<BoundingSurfaceFinder> surfaces;  // made on first use
};

/// The valid depth readings of each network pixel's block: their sum over the block's area
/// (each reading clamped to `max_depth_m`) into scratch.depth_small and their fraction of it
/// into scratch.valid_small, both size x size; their mean is the one over the other. The filled
/// input is made from these, so after writeNetworkInput in DepthGaps::kFilled they are already
/// there, each reading clamped to InputFormat::farReadingM().
void sumValidDepth(const cv::Mat& depth, int size, InputScratch& scratch,
                   float max_depth_m = static_cast<float>(kFarDepthM));

/// The plane search of a cleared input: the finder's defaults but a tolerance that grows only
/// 1 mm/m^2 with depth (not 4), so that the feet of an object standing on the floor stay in
/// view (at 4 m 3.6 cm above the floor, not 8.4); chosen on validation scenes in rooms with each
/// depth-sensor model (doc/TRAINING.md, "Floors and walls as the void for the agent").
BoundingSurfaceOptions clearedInputSurfaceOptions();

/// Finds the bounding surfaces (floors, walls) of the view (`image_size`, seen with
/// `intrinsics`) whose valid depths sumValidDepth has summed into `scratch` at the network's
/// size: each network pixel's depth is the mean of its block's readings, none (NaN) where fewer
/// than half of it read, since a mean over a few speckles is no surface; times `depth_scale`
/// (a cleared input's InputFormat::depthScale(): a scene scaled with its sphere is searched as
/// the same scene at 4 m, with the tolerances of 4 m). Writes scratch.grid_depth (scaled) and
/// scratch.on_surface (255 on a surface).
void findGridBoundingSurfaces(const CameraIntrinsics& intrinsics, const cv::Size& image_size,
                              BoundingSurfaceFinder& finder, InputScratch& scratch,
                              double depth_scale = 1.0);

/// Writes the normalised input of `rgb` (CV_8UC3) and `depth` (CV_32FC1 [m], NaN = nothing) in
/// `format` into `out` (format.channels() * size * size floats, channel-major), of the view's crop
/// (viewCropRect) when the format has one. Throws InvalidArgumentError on
/// wrong types or sizes, and for a format that clears bounding surfaces or has a
/// view_field_of_view (they need intrinsics).
void writeNetworkInput(const cv::Mat& rgb, const cv::Mat& depth, const InputFormat& format,
                       InputScratch& scratch, float* out);

/// The same for a camera with `intrinsics` (of rgb and depth): any format, of the view's part
/// seenViewRect gives. Throws InvalidArgumentError also when the format clears bounding surfaces
/// or has a view_field_of_view and the intrinsics have no focal length.
void writeNetworkInput(const cv::Mat& rgb, const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                       const InputFormat& format, InputScratch& scratch, float* out);

}  // namespace learning
}  // namespace occlusion_env
