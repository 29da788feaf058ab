// A trained network on disk: `<name>.pt` (the parameters and buffers, torch::save) beside
// `<name>.json` (its NetworkConfig, how it was made and its metrics). Loading checks both and
// refuses a missing, corrupt or mismatched file with a message that says which.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "occlusion_env/learning/multitask_unet.hpp"

namespace occlusion_env {
namespace learning {

/// Writes `path` (.pt) and its manifest (path with .json) holding `config` and `info`.
void saveModel(MultiTaskUNet& network, const std::string& path, const nlohmann::json& info);

struct LoadedModel {
  MultiTaskUNet network{nullptr};
  nlohmann::json manifest;
};

/// Loads a model saved by saveModel(), in eval mode. Throws InvalidArgumentError when the file
/// or its manifest is missing, unreadable or does not fit the manifest's network.
LoadedModel loadModel(const std::string& path);

/// "<path without .pt>.json"
std::string manifestPathFor(const std::string& model_path);

/// The manifest beside `path`, parsed. Throws InvalidArgumentError when the model file or its
/// manifest is missing or the manifest is not JSON.
nlohmann::json readManifest(const std::string& path);

/// Loads the parameters and buffers saved in `path` into `module`, refusing (InvalidArgumentError
/// naming `what`) a corrupt file or one whose tensors do not have `module`'s shapes.
void loadCheckedParameters(torch::nn::Module& module, const std::string& path,
                           const std::string& what);

}  // namespace learning
}  // namespace occlusion_env
