// A check's frames as pictures (occlusion_train --check ... --montage FILE.png): a row per
// world and depth sensor, a few frames each as the network sees them, its estimate over the
// label, so that where an IoU is lost can be seen rather than guessed.
//
//   each frame: [RGB input, label green, estimate red, both yellow] [depth input, near bright]
//               caption: label / estimate [network px], the frame's IoU
#pragma once

#include <torch/torch.h>

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "occlusion_env/learning/multitask_unet.hpp"
#include "occlusion_env/learning/training.hpp"

namespace occlusion_env {
namespace learning {

/// Per condition (framesByCondition's, in name order), up to `per_condition` frame
/// indices spread evenly over that condition's frames in their order: first, ..., the same
/// picks on every run. `conditions` has one entry per frame (loadCheckFrames').
std::vector<std::pair<std::string, std::vector<int64_t>>> montageFrames(
    const std::vector<std::string>& conditions, int per_condition);

/// One frame's input (`input` [4 or 5, S, S] float, network_input.hpp) with `label` and `estimate`
/// ([S, S], 0 / 1) over its RGB, as a BGR 8-bit tile of `tile_px` x `tile_px` (nearest
/// neighbour): label only green, estimate only red, both yellow, each blended half with the RGB;
/// the rest the RGB as the network sees it.
cv::Mat overlayTile(const torch::Tensor& input, const torch::Tensor& label,
                    const torch::Tensor& estimate, int tile_px);

/// The depth channel of `input` as a grey BGR tile: near white, the far (kFarDepthM) and missing
/// depth black.
cv::Mat depthTile(const torch::Tensor& input, int tile_px);

/// The contact sheet: montageFrames' picks, run through `network` (eval mode, no gradients;
/// the estimate where the occlusion logit is > 0, as evaluate()'s IoU), a row per condition
/// with its name, each frame as overlayTile and depthTile side by side with its caption.
cv::Mat checkMontage(MultiTaskUNet& network, const Samples& frames,
                     const std::vector<std::string>& conditions, int per_condition = 6,
                     int tile_px = 128);

}  // namespace learning
}  // namespace occlusion_env
