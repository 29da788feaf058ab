#include "occlusion_env/learning/network_input.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace learning {
namespace {

constexpr float kFar = static_cast<float>(kFarDepthM);
constexpr int kMinValidNeighbours = 4;  // of 8, for a gap to be filled (DepthGaps::kFilled)

InvalidArgumentError noIntrinsicsForTheAngleOfView() {
  return InvalidArgumentError(
      "network input: this model sees a fixed angle of view (view_field_of_view), which needs "
      "the camera's intrinsics; none were given");
}

float normalisedDepth(float metres) {
  return normalisedInput(metres / kFar);
}

// `source` resized to `target` by area averaging, or `source` itself at that size already.
void resizeTo(const cv::Mat& source, const cv::Size& target, cv::Mat& resized) {
  if (source.size() == target) {
    resized = source;
  } else {
    cv::resize(source, resized, target, 0, 0, cv::INTER_AREA);
  }
}

// DepthGaps::kFar: missing = far, then averaged.
void writeDepthFar(const cv::Mat& depth, int size, float scale, InputScratch& scratch, float* out) {
  scratch.depth_filled.create(depth.size(), CV_32FC1);
  for (int row = 0; row < depth.rows; ++row) {
    const float* in = depth.ptr<float>(row);
    float* filled = scratch.depth_filled.ptr<float>(row);
    for (int col = 0; col < depth.cols; ++col) {
      const float d = in[col];
      filled[col] = std::isfinite(d) ? std::min(std::max(d * scale, 0.0f), kFar) : kFar;
    }
  }
  resizeTo(scratch.depth_filled, cv::Size(size, size), scratch.depth_small);
  for (int row = 0; row < size; ++row) {
    const float* depths = scratch.depth_small.ptr<float>(row);
    for (int col = 0; col < size; ++col) out[row * size + col] = normalisedDepth(depths[col]);
  }
}

// The mean depth of the valid 8-neighbours of (row, col) at the network's size, or infinity
// (far at any scale) when fewer than kMinValidNeighbours are valid.
float filledGap(const cv::Mat& depth_sum, const cv::Mat& valid_fraction, int row, int col) {
  int count = 0;
  float sum = 0.0f;
  for (int r = std::max(0, row - 1); r <= std::min(depth_sum.rows - 1, row + 1); ++r) {
    for (int c = std::max(0, col - 1); c <= std::min(depth_sum.cols - 1, col + 1); ++c) {
      const float fraction = valid_fraction.at<float>(r, c);
      if (fraction <= 0.0f) continue;  // (row, col) itself included: it has none
      sum += depth_sum.at<float>(r, c) / fraction;
      ++count;
    }
  }
  return count >= kMinValidNeighbours ? sum / count : std::numeric_limits<float>::infinity();
}

// DepthGaps::kFilled: averaged over valid pixels; gaps filled from their neighbours. Depth
// times `format`'s scale, each reading clamped at its far first (so a block's mean is the one at
// 4 m).
void writeDepthFilled(const cv::Mat& depth, const InputFormat& format, InputScratch& scratch,
                      float* out) {
  const int size = format.size;
  const float scale = static_cast<float>(format.depthScale());
  sumValidDepth(depth, size, scratch, format.farReadingM());
  for (int row = 0; row < size; ++row) {
    const float* sums = scratch.depth_small.ptr<float>(row);
    const float* fractions = scratch.valid_small.ptr<float>(row);
    for (int col = 0; col < size; ++col) {
      const float metres = fractions[col] > 0.0f
                               ? sums[col] / fractions[col]
                               : filledGap(scratch.depth_small, scratch.valid_small, row, col);
      out[row * size + col] = normalisedDepth(std::min(metres * scale, kFar));
    }
  }
}

}  // namespace

void sumValidDepth(const cv::Mat& depth, int size, InputScratch& scratch, float max_depth_m) {
  scratch.depth_filled.create(depth.size(), CV_32FC1);
  scratch.valid.create(depth.size(), CV_32FC1);
  for (int row = 0; row < depth.rows; ++row) {
    const float* in = depth.ptr<float>(row);
    float* filled = scratch.depth_filled.ptr<float>(row);
    float* valid = scratch.valid.ptr<float>(row);
    for (int col = 0; col < depth.cols; ++col) {
      const float d = in[col];
      const bool seen = std::isfinite(d) && d > 0.0f;
      filled[col] = seen ? std::min(d, max_depth_m) : 0.0f;
      valid[col] = seen ? 1.0f : 0.0f;
    }
  }
  const cv::Size target(size, size);
  resizeTo(scratch.depth_filled, target, scratch.depth_small);  // the valid depths' sum / area
  resizeTo(scratch.valid, target, scratch.valid_small);         // the valid fraction
}

namespace {

// The images resized and normalised into `out`, in `format` but for its bounding surfaces.
void writeImages(const cv::Mat& rgb, const cv::Mat& depth, const InputFormat& format,
                 InputScratch& scratch, float* out) {
  if (rgb.type() != CV_8UC3 || depth.type() != CV_32FC1 || rgb.size() != depth.size() ||
      rgb.empty()) {
    throw InvalidArgumentError("network input: needs CV_8UC3 RGB and CV_32FC1 depth of one size");
  }
  const int size = format.size;
  resizeTo(rgb, cv::Size(size, size), scratch.rgb_small);
  const std::size_t plane = static_cast<std::size_t>(size) * size;
  for (int row = 0; row < size; ++row) {
    const cv::Vec3b* pixels = scratch.rgb_small.ptr<cv::Vec3b>(row);
    for (int col = 0; col < size; ++col) {
      const std::size_t i = static_cast<std::size_t>(row) * size + col;
      for (int c = 0; c < 3; ++c) out[c * plane + i] = normalisedInput(pixels[col][c] / 255.0f);
    }
  }
  const float scale = static_cast<float>(format.depthScale());
  if (format.depth_gaps == DepthGaps::kFilled) {
    writeDepthFilled(depth, format, scratch, out + 3 * plane);
  } else {
    writeDepthFar(depth, size, scale, scratch, out + 3 * plane);
  }
  if (!format.valid_fraction_channel) return;
  if (format.depth_gaps != DepthGaps::kFilled) {
    sumValidDepth(depth, size, scratch, format.farReadingM());
  }
  float* valid_out = out + 4 * plane;
  for (int row = 0; row < size; ++row) {
    const float* fractions = scratch.valid_small.ptr<float>(row);
    for (int col = 0; col < size; ++col)
      valid_out[row * size + col] = normalisedInput(fractions[col]);
  }
}

// The intrinsics of the network's size x size grid over an image of `image_size` seen with
// `intrinsics` (pixel centres map to pixel centres).
CameraIntrinsics gridIntrinsics(const CameraIntrinsics& intrinsics, const cv::Size& image_size,
                                int size) {
  CameraIntrinsics grid = intrinsics;
  const double sx = static_cast<double>(size) / image_size.width;
  const double sy = static_cast<double>(size) / image_size.height;
  grid.width = grid.height = size;
  grid.fx *= sx;
  grid.fy *= sy;
  grid.cx = (intrinsics.cx + 0.5) * sx - 0.5;
  grid.cy = (intrinsics.cy + 0.5) * sy - 0.5;
  return grid;
}

}  // namespace

double InputFormat::depthScale() const {
  if (!depth_per_radius) return 1.0;
  if (!(std::isfinite(radius_m) && radius_m > 0.0)) {
    throw InvalidArgumentError(
        "network input: this model reads depth relative to the camera's distance from the "
        "sphere's centre (depth_reference: radius), and none was given");
  }
  return kWorkingRadiusM / radius_m;
}

InputFormat InputFormat::atRadius(double camera_radius_m) const {
  InputFormat format = *this;
  format.radius_m = camera_radius_m;
  return format;
}

cv::Rect viewCropRect(const cv::Size& image_size, double view_crop) {
  if (!(view_crop > 0.0 && view_crop <= 1.0)) {
    throw InvalidArgumentError("network input: view_crop must lie in (0, 1]");
  }
  if (view_crop == 1.0) return cv::Rect(cv::Point(0, 0), image_size);
  const int width = std::max(1, static_cast<int>(std::lround(view_crop * image_size.width)));
  const int height = std::max(1, static_cast<int>(std::lround(view_crop * image_size.height)));
  return cv::Rect((image_size.width - width) / 2, (image_size.height - height) / 2, width, height);
}

cv::Rect seenViewRect(const cv::Size& image_size, const CameraIntrinsics& intrinsics,
                      const InputFormat& format) {
  if (format.view_field_of_view == 0.0) return viewCropRect(image_size, format.view_crop);
  if (!(format.view_field_of_view > 0.0 && format.view_field_of_view < M_PI)) {
    throw InvalidArgumentError("network input: view_field_of_view must lie in (0, pi) rad");
  }
  if (!(intrinsics.fx > 0.0 && intrinsics.fy > 0.0)) throw noIntrinsicsForTheAngleOfView();
  const double tangent = std::tan(0.5 * format.view_field_of_view);
  const double half_width = intrinsics.fx * tangent;   // [px]
  const double half_height = intrinsics.fy * tangent;  // [px]
  // Pixel i spans [i - 0.5, i + 0.5] about the principal point's coordinates.
  const int left = static_cast<int>(std::lround(intrinsics.cx + 0.5 - half_width));
  const int top = static_cast<int>(std::lround(intrinsics.cy + 0.5 - half_height));
  const int right = static_cast<int>(std::lround(intrinsics.cx + 0.5 + half_width));
  const int bottom = static_cast<int>(std::lround(intrinsics.cy + 0.5 + half_height));
  return cv::Rect(left, top, std::max(1, right - left), std::max(1, bottom - top));
}

cv::Mat viewPart(const cv::Mat& image, const cv::Rect& rect, const cv::Scalar& fill,
                 cv::Mat& padded) {
  const cv::Rect whole(cv::Point(0, 0), image.size());
  if ((rect & whole) == rect) return image(rect);
  padded.create(rect.size(), image.type());
  padded.setTo(fill);
  const cv::Rect inside = rect & whole;
  if (!inside.empty()) image(inside).copyTo(padded(inside - rect.tl()));
  return padded;
}

CameraIntrinsics croppedIntrinsics(const CameraIntrinsics& intrinsics, const cv::Rect& crop) {
  CameraIntrinsics cropped = intrinsics;
  cropped.width = crop.width;
  cropped.height = crop.height;
  cropped.cx -= crop.x;
  cropped.cy -= crop.y;
  return cropped;
}

BoundingSurfaceOptions clearedInputSurfaceOptions() {
  BoundingSurfaceOptions options;
  options.tolerance_per_m2 = 0.001;
  return options;
}

void findGridBoundingSurfaces(const CameraIntrinsics& intrinsics, const cv::Size& image_size,
                              BoundingSurfaceFinder& finder, InputScratch& scratch,
                              double depth_scale) {
  const int size = scratch.depth_small.rows;
  const float scale = static_cast<float>(depth_scale);
  scratch.grid_depth.create(size, size, CV_32FC1);
  for (int row = 0; row < size; ++row) {
    const float* sum = scratch.depth_small.ptr<float>(row);
    const float* fraction = scratch.valid_small.ptr<float>(row);
    float* out = scratch.grid_depth.ptr<float>(row);
    for (int col = 0; col < size; ++col) {
      out[col] = fraction[col] >= 0.5f ? scale * sum[col] / fraction[col]
                                       : std::numeric_limits<float>::quiet_NaN();
    }
  }
  finder.find(scratch.grid_depth, gridIntrinsics(intrinsics, image_size, size), scratch.on_surface);
}

void writeNetworkInput(const cv::Mat& rgb, const cv::Mat& depth, const InputFormat& format,
                       InputScratch& scratch, float* out) {
  if (format.clear_bounding_surfaces) {
    throw InvalidArgumentError(
        "network input: this model clears the view's floors and walls (bounding_surfaces: "
        "cleared), which needs the camera's intrinsics; frames without them (the datasets') "
        "cannot be its input");
  }
  if (format.view_field_of_view > 0.0) throw noIntrinsicsForTheAngleOfView();
  if (format.view_crop != 1.0 && !rgb.empty() && rgb.size() == depth.size()) {
    const cv::Rect crop = viewCropRect(rgb.size(), format.view_crop);
    writeImages(rgb(crop), depth(crop), format, scratch, out);
    return;
  }
  writeImages(rgb, depth, format, scratch, out);
}

void writeNetworkInput(const cv::Mat& rgb, const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                       const InputFormat& format, InputScratch& scratch, float* out) {
  if (format.clear_bounding_surfaces && !(intrinsics.fx > 0.0 && intrinsics.fy > 0.0)) {
    throw InvalidArgumentError(
        "network input: this model clears the view's floors and walls (bounding_surfaces: "
        "cleared) and needs the camera's intrinsics; none were given");
  }
  if (format.cropsView() && !rgb.empty() && rgb.size() == depth.size()) {
    // The crop, as if a camera saw only it (no pixel copied unless it reaches beyond the image:
    // black and no depth there).
    const cv::Rect crop = seenViewRect(rgb.size(), intrinsics, format);
    if (crop != cv::Rect(cv::Point(0, 0), rgb.size())) {
      InputFormat whole = format;
      whole.view_crop = 1.0;
      whole.view_field_of_view = 0.0;
      const float no_depth = std::numeric_limits<float>::quiet_NaN();
      writeNetworkInput(viewPart(rgb, crop, cv::Scalar::all(0), scratch.rgb_padded),
                        viewPart(depth, crop, cv::Scalar::all(no_depth), scratch.depth_padded),
                        croppedIntrinsics(intrinsics, crop), whole, scratch, out);
      return;
    }  // else the whole view: the paper's camera at the model's angle
  }
  writeImages(rgb, depth, format, scratch, out);
  if (!format.clear_bounding_surfaces) return;
  const int size = format.size;
  if (!format.sumsValidDepth()) sumValidDepth(depth, size, scratch, format.farReadingM());
  if (!scratch.surfaces) {
    scratch.surfaces = std::make_unique<BoundingSurfaceFinder>(clearedInputSurfaceOptions());
  }
  // Searched at the depth the network reads (relative to the radius if the model's is), so that
  // the tolerances are those of the scene at 4 m whatever its scale.
  findGridBoundingSurfaces(intrinsics, rgb.size(), *scratch.surfaces, scratch, format.depthScale());
  // The void: black, far, nothing read; on a bounding surface, or where no depth was read at
  // all.
  const std::size_t plane = static_cast<std::size_t>(size) * size;
  for (int row = 0; row < size; ++row) {
    const std::uint8_t* surface = scratch.on_surface.ptr<std::uint8_t>(row);
    const float* valid_fraction = scratch.valid_small.ptr<float>(row);
    for (int col = 0; col < size; ++col) {
      if (!surface[col] && valid_fraction[col] > 0.0f) continue;
      const std::size_t i = static_cast<std::size_t>(row) * size + col;
      out[i] = out[plane + i] = out[2 * plane + i] = kBlackInput;
      out[3 * plane + i] = kNoDepthInput;
      if (format.valid_fraction_channel) out[4 * plane + i] = kNothingReadInput;
    }
  }
}

}  // namespace learning
}  // namespace occlusion_env
