#include "occlusion_env/learning/model_file.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/text_file.hpp"

namespace occlusion_env {
namespace learning {

std::string manifestPathFor(const std::string& model_path) {
  std::filesystem::path path(model_path);
  return path.replace_extension(".json").string();
}

void saveModel(MultiTaskUNet& network, const std::string& path, const nlohmann::json& info) {
  torch::save(network, path);
  nlohmann::json manifest = info;
  manifest["kind"] = "multitask_unet";
  manifest["network"] = network->config().toJson();
  manifest["file"] = std::filesystem::path(path).filename().string();
  writeTextFile(manifestPathFor(path), manifest.dump(2) + "\n");
}

nlohmann::json readManifest(const std::string& path) {
  if (path.empty()) throw InvalidArgumentError("model: no file given");
  if (!std::filesystem::is_regular_file(path)) {
    throw InvalidArgumentError("model file " + path + " does not exist");
  }
  const std::string manifest_path = manifestPathFor(path);
  std::ifstream in(manifest_path);
  if (!in) {
    throw InvalidArgumentError("model " + path + ": its manifest " + manifest_path +
                               " is missing (a model is the .pt and the .json beside it)");
  }
  try {
    return nlohmann::json::parse(in);
  } catch (const std::exception& error) {
    throw InvalidArgumentError("model " + path + ": unreadable manifest " + manifest_path + ": " +
                               error.what());
  }
}

void loadCheckedParameters(torch::nn::Module& module, const std::string& path,
                           const std::string& what, torch::Dtype stored) {
  // Loading replaces each tensor with the stored one whatever its shape: compare the shapes with
  // those the module was built with.
  std::map<std::string, std::vector<int64_t>> expected;
  for (const auto& item : module.named_parameters())
    expected[item.key()] = item.value().sizes().vec();
  for (const auto& item : module.named_buffers()) expected[item.key()] = item.value().sizes().vec();
  try {
    torch::serialize::InputArchive archive;
    archive.load_from(path);
    // A stored tensor replaces the module's only where their types agree: load in the stored
    // type, then run in float32.
    if (stored != torch::kFloat32) module.to(stored);
    module.load(archive);
    if (stored != torch::kFloat32) module.to(torch::kFloat32);
  } catch (const c10::Error& error) {
    const std::string message = error.what_without_backtrace();
    throw InvalidArgumentError("model " + path + " is corrupt or does not match " + what + ": " +
                               message.substr(0, 300));
  }
  for (const auto& item : module.named_parameters()) {
    if (item.value().sizes().vec() != expected.at(item.key())) {
      throw InvalidArgumentError("model " + path + " does not match " + what + ": " + item.key() +
                                 " has shape " + c10::str(item.value().sizes()));
    }
  }
}

namespace {
constexpr const char* kHalfPrecisionWeights = "float16";
}  // namespace

torch::Dtype storedWeightType(const nlohmann::json& manifest, const std::string& path) {
  const std::string weights = manifest.value("weights", std::string("float32"));
  if (weights == "float32") return torch::kFloat32;
  if (weights == kHalfPrecisionWeights) return torch::kFloat16;
  throw InvalidArgumentError("model " + path + ": its manifest's weights \"" + weights +
                             "\" are neither float32 nor float16");
}

void saveHalfPrecisionCopy(const std::string& source, const std::string& path) {
  LoadedModel model = loadModel(source);  // refuses a missing or broken source first
  if (std::filesystem::exists(path) && std::filesystem::equivalent(source, path)) {
    throw InvalidArgumentError("half-precision copy: " + path + " is the source model itself");
  }
  model.network->to(torch::kFloat16);
  torch::save(model.network, path);
  nlohmann::json manifest = model.manifest;
  manifest["weights"] = kHalfPrecisionWeights;
  manifest["half_precision_of"] = source;
  manifest["file"] = std::filesystem::path(path).filename().string();
  writeTextFile(manifestPathFor(path), manifest.dump(2) + "\n");
}

LoadedModel loadModel(const std::string& path) {
  LoadedModel model;
  model.manifest = readManifest(path);
  if (model.manifest.value("kind", "multitask_unet") != "multitask_unet") {
    throw InvalidArgumentError("model " + path + " is a " +
                               model.manifest.value("kind", std::string()) +
                               ", not a multi-task network");
  }
  NetworkConfig config;
  try {
    config = NetworkConfig::fromJson(model.manifest.at("network"));
  } catch (const std::exception& error) {
    throw InvalidArgumentError("model " + path + ": unreadable manifest " + manifestPathFor(path) +
                               ": " + error.what());
  }
  model.network = MultiTaskUNet(config);
  loadCheckedParameters(*model.network, path,
                        "its manifest's network (" + config.toJson().dump() + ")",
                        storedWeightType(model.manifest, path));
  model.network->eval();
  return model;
}

}  // namespace learning
}  // namespace occlusion_env
