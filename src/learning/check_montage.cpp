#include "occlusion_env/learning/check_montage.hpp"

#include <algorithm>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace learning {
namespace {

constexpr int kCaptionPx = 18;     // below each frame's tiles
constexpr int kNameStripPx = 200;  // the condition's name, left of its row
constexpr int kGapPx = 4;          // between frames

// A [S, S] float tensor in [0, 1] as an 8-bit single-channel image of its size.
cv::Mat toByteImage(const torch::Tensor& unit) {
  const torch::Tensor bytes =
      (unit.clamp(0.0, 1.0) * 255.0).round().to(torch::kUInt8).contiguous().cpu();
  return cv::Mat(static_cast<int>(bytes.size(0)), static_cast<int>(bytes.size(1)), CV_8UC1,
                 const_cast<uint8_t*>(bytes.data_ptr<uint8_t>()))
      .clone();
}

// Channel c of a network input back to [0, 1] (network_input.hpp: (x - 0.5) / 0.25).
torch::Tensor unitChannel(const torch::Tensor& input, int c) {
  return input[c].to(torch::kFloat) * 0.25 + 0.5;
}

void putCaption(cv::Mat& image, const std::string& text, cv::Point origin, double scale = 0.4) {
  cv::putText(image, text, origin, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(255, 255, 255), 1,
              cv::LINE_AA);
}

}  // namespace

std::vector<std::pair<std::string, std::vector<int64_t>>> montageFrames(
    const std::vector<std::string>& conditions, int per_condition) {
  if (per_condition < 1)
    throw InvalidArgumentError("montageFrames: per_condition must be at least 1");
  std::vector<std::pair<std::string, std::vector<int64_t>>> picks;
  for (const auto& [condition, indices] : framesByCondition(conditions)) {
    const size_t count = std::min<size_t>(per_condition, indices.size());
    std::vector<int64_t> chosen;
    for (size_t k = 0; k < count; ++k) chosen.push_back(indices[k * indices.size() / count]);
    picks.emplace_back(condition, chosen);
  }
  return picks;
}

cv::Mat overlayTile(const torch::Tensor& input, const torch::Tensor& label,
                    const torch::Tensor& estimate, int tile_px) {
  if (input.dim() != 3 || input.size(0) < 4)
    throw InvalidArgumentError("overlayTile: input must be [4 or 5, S, S]");
  std::vector<cv::Mat> bgr = {toByteImage(unitChannel(input, 2)),
                              toByteImage(unitChannel(input, 1)),
                              toByteImage(unitChannel(input, 0))};
  cv::Mat image;
  cv::merge(bgr, image);
  const cv::Mat is_label = toByteImage(label.to(torch::kFloat));
  const cv::Mat is_estimate = toByteImage(estimate.to(torch::kFloat));
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const bool l = is_label.at<uint8_t>(y, x) > 0, e = is_estimate.at<uint8_t>(y, x) > 0;
      if (!l && !e) continue;
      const cv::Vec3b colour = l && e ? cv::Vec3b(0, 255, 255)       // yellow
                                      : (l ? cv::Vec3b(0, 255, 0)    // green
                                           : cv::Vec3b(0, 0, 255));  // red
      cv::Vec3b& pixel = image.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) pixel[c] = static_cast<uint8_t>((pixel[c] + colour[c]) / 2);
    }
  }
  cv::Mat tile;
  cv::resize(image, tile, cv::Size(tile_px, tile_px), 0, 0, cv::INTER_NEAREST);
  return tile;
}

cv::Mat depthTile(const torch::Tensor& input, int tile_px) {
  if (input.dim() != 3 || input.size(0) < 4)
    throw InvalidArgumentError("depthTile: input must be [4 or 5, S, S]");
  const cv::Mat grey = toByteImage(1.0 - unitChannel(input, 3));  // far (1) -> black
  cv::Mat bgr, tile;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  cv::resize(bgr, tile, cv::Size(tile_px, tile_px), 0, 0, cv::INTER_NEAREST);
  return tile;
}

cv::Mat checkMontage(MultiTaskUNet& network, const Samples& frames,
                     const std::vector<std::string>& conditions, int per_condition, int tile_px) {
  if (static_cast<int64_t>(conditions.size()) != frames.size())
    throw InvalidArgumentError("checkMontage: one condition per frame");
  if (tile_px < 16) throw InvalidArgumentError("checkMontage: tile_px must be at least 16");
  const auto picks = montageFrames(conditions, per_condition);
  const int frame_width = 2 * tile_px + kGapPx;
  const int row_height = tile_px + kCaptionPx + kGapPx;
  cv::Mat sheet(std::max<int>(1, static_cast<int>(picks.size())) * row_height,
                kNameStripPx + per_condition * frame_width, CV_8UC3, cv::Scalar(40, 40, 40));
  torch::NoGradGuard no_grad;
  const bool was_training = network->is_training();
  network->eval();
  for (size_t row = 0; row < picks.size(); ++row) {
    const auto& [condition, indices] = picks[row];
    const int top = static_cast<int>(row) * row_height;
    putCaption(sheet, condition, cv::Point(6, top + tile_px / 2), 0.45);
    const torch::Tensor index = torch::tensor(indices, torch::kLong);
    const torch::Tensor inputs = frames.inputs.index_select(0, index).to(torch::kFloat);
    const torch::Tensor labels = frames.masks.index_select(0, index);
    const torch::Tensor estimates = network->forward(inputs).occlusion_logits > 0.0;
    for (size_t k = 0; k < indices.size(); ++k) {
      const int left = kNameStripPx + static_cast<int>(k) * frame_width;
      const torch::Tensor label = labels[k][0], estimate = estimates[k][0];
      overlayTile(inputs[k], label, estimate, tile_px)
          .copyTo(sheet(cv::Rect(left, top, tile_px, tile_px)));
      depthTile(inputs[k], tile_px).copyTo(sheet(cv::Rect(left + tile_px, top, tile_px, tile_px)));
      const int64_t label_px = label.sum().item<int64_t>();
      const int64_t estimate_px = estimate.sum().item<int64_t>();
      const int64_t both = (label.to(torch::kBool) & estimate).sum().item<int64_t>();
      const int64_t either = label_px + estimate_px - both;
      char caption[96];
      if (either > 0) {
        std::snprintf(caption, sizeof caption, "#%lld  label %lld  est %lld  IoU %.2f",
                      static_cast<long long>(indices[k]), static_cast<long long>(label_px),
                      static_cast<long long>(estimate_px), static_cast<double>(both) / either);
      } else {
        std::snprintf(caption, sizeof caption, "#%lld  label 0  est 0",
                      static_cast<long long>(indices[k]));
      }
      putCaption(sheet, caption, cv::Point(left + 2, top + tile_px + kCaptionPx - 5));
    }
  }
  if (was_training) network->train();
  return sheet;
}

}  // namespace learning
}  // namespace occlusion_env
