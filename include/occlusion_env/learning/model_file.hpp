// A trained network on disk: `<name>.pt` (the parameters and buffers, torch::save) beside
// `<name>.json` (its NetworkConfig, how it was made and its metrics). Loading checks both and
// refuses a missing, corrupt or mismatched file with a message that says which. The weights are
// stored in float32, or, for shipping a wide network, as the manifest's "weights" says: "float16"
// (half the file) or "uint8" (a quarter: each layer's weights as 8-bit codes per output channel);
// however stored, they are loaded and run in float32.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "occlusion_env/learning/multitask_unet.hpp"

namespace occlusion_env {
namespace learning {

/// Writes `path` (.pt) and its manifest (path with .json) holding `config` and `info`.
void saveModel(MultiTaskUNet& network, const std::string& path, const nlohmann::json& info);

/// How a model file stores its weights (the manifest's "weights": float32, float16 or uint8).
enum class WeightStorage { kFloat32, kFloat16, kUint8 };

/// Writes a copy of the model at `source` to `path` with its weights stored as `storage` (float16
/// or uint8), and its manifest: the source's, with "weights" and "copy_of": `source`. Throws
/// InvalidArgumentError as loadModel() does, for float32, or when `path` is `source`.
void saveCompactCopy(const std::string& source, const std::string& path, WeightStorage storage);

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

/// How the weights of the model at `path` are stored, from its manifest's "weights" (absent:
/// float32). Throws InvalidArgumentError for any other than float32, float16 and uint8.
WeightStorage storedWeights(const nlohmann::json& manifest, const std::string& path);

/// Loads the parameters and buffers saved in `path` into `module`, refusing (InvalidArgumentError
/// naming `what`) a corrupt file or one whose tensors do not have `module`'s shapes. `stored`:
/// how they were saved; each tensor keeps the type `module` was built with (float32 weights,
/// integer counters), whatever type the file holds it in.
void loadCheckedParameters(torch::nn::Module& module, const std::string& path,
                           const std::string& what, WeightStorage stored = WeightStorage::kFloat32);

/// Reads the tensors `archive` holds for `module` (as torch::save(module) wrote them, or an
/// archive it read into) into the module's own, each converted to the module's type; refuses as
/// loadCheckedParameters does, naming `path` and `what`. Use it instead of Module::load, which
/// makes a tensor view the stored one's memory in its own type.
void readParameters(torch::nn::Module& module, torch::serialize::InputArchive& archive,
                    const std::string& path, const std::string& what);

/// Runs `read`, a trainer's reading of the checkpoint in its output folder `run_dir` on resume.
/// libtorch's and JSON's errors from a damaged or incomplete checkpoint (a run killed while
/// writing it, a disk that filled) become an InvalidArgumentError naming the folder and what to
/// do; the trainers' own refusals pass through as they are.
void readCheckpoint(const std::string& run_dir, const std::function<void()>& read);

}  // namespace learning
}  // namespace occlusion_env
