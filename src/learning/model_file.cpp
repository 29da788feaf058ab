#include "occlusion_env/learning/model_file.hpp"

#include <filesystem>
#include <fstream>
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

namespace {

// A library's error message, cut to a length that reads in one of our messages.
std::string briefReason(const std::string& message) {
  return message.substr(0, 300);
}

// An 8-bit file holds the module's tensors under their index among its parameters and then its
// buffers ("t<i>"), in the order the module lists them. A floating-point tensor of two or more
// dimensions (a convolution's or a linear layer's weights) is stored as uint8 codes ("q<i>") with,
// per output channel (its first dimension), the lowest value ("low<i>") and the step between codes
// ("step<i>"), both float32: value = low + code * step, within step / 2 of the original.
// Smaller tensors (the heads, the first and last layers: 1-2 % of a U-Net's weights, where a
// small error turns the escape direction most) stay float32.
constexpr int64_t kEightBitsFrom = 16384;

std::string eightBitKey(const char* what, std::size_t index) {
  return what + std::to_string(index);
}

bool storedInEightBits(const torch::Tensor& tensor) {
  return tensor.is_floating_point() && tensor.dim() >= 2 && tensor.numel() >= kEightBitsFrom;
}

std::vector<std::pair<std::string, torch::Tensor>> tensorsOf(const torch::nn::Module& module) {
  std::vector<std::pair<std::string, torch::Tensor>> tensors;
  for (const auto& item : module.named_parameters()) tensors.emplace_back(item.key(), item.value());
  for (const auto& item : module.named_buffers()) tensors.emplace_back(item.key(), item.value());
  return tensors;
}

torch::Tensor readTensor(torch::serialize::InputArchive& archive, const std::string& key) {
  c10::IValue value;
  archive.read(key, value);
  return value.toTensor();
}

void saveEightBits(const torch::nn::Module& module, const std::string& path) {
  torch::NoGradGuard no_grad;
  torch::serialize::OutputArchive archive;
  const auto tensors = tensorsOf(module);
  for (std::size_t i = 0; i < tensors.size(); ++i) {
    const torch::Tensor tensor = tensors[i].second.detach().to(torch::kCPU);
    if (!storedInEightBits(tensor)) {
      archive.write(eightBitKey("t", i), c10::IValue(tensor.clone()));
      continue;
    }
    const torch::Tensor rows = tensor.to(torch::kFloat32).reshape({tensor.size(0), -1});
    const torch::Tensor low = std::get<0>(rows.min(1));
    const torch::Tensor high = std::get<0>(rows.max(1));
    // A channel whose values are all equal keeps them exactly: any step, every code 0.
    const torch::Tensor step =
        torch::where(high > low, (high - low) / 255.0, torch::ones_like(low));
    const torch::Tensor codes =
        ((rows - low.unsqueeze(1)) / step.unsqueeze(1)).round().clamp(0, 255).to(torch::kUInt8);
    archive.write(eightBitKey("q", i), c10::IValue(codes.reshape(tensor.sizes()).contiguous()));
    archive.write(eightBitKey("low", i), c10::IValue(low.contiguous()));
    archive.write(eightBitKey("step", i), c10::IValue(step.contiguous()));
  }
  archive.save_to(path);
}

// Whether the storage of `tensor` holds every element its sizes and strides address.
bool holdsItsElements(const torch::Tensor& tensor) {
  if (tensor.numel() == 0) return true;
  int64_t last = tensor.storage_offset();
  for (int64_t d = 0; d < tensor.dim(); ++d) last += (tensor.size(d) - 1) * tensor.stride(d);
  return static_cast<int64_t>(tensor.storage().nbytes()) >= (last + 1) * tensor.element_size();
}

// Copies `stored`, a file's tensor for the module tensor `name`, into `target`, converted to
// target's type; refuses (naming `path` and `what`) another shape or fewer stored bytes than the
// shape needs.
void copyStoredTensor(const torch::Tensor& target, const torch::Tensor& stored,
                      const std::string& name, const std::string& path, const std::string& what) {
  if (stored.sizes() != target.sizes()) {
    throw InvalidArgumentError("model " + path + " does not match " + what + ": " + name +
                               " has shape " + c10::str(stored.sizes()));
  }
  if (!holdsItsElements(stored)) {
    throw InvalidArgumentError("model " + path + " is corrupt: " + name +
                               " holds fewer bytes than its shape needs");
  }
  target.copy_(stored);
}

// Fills every tensor of `module` from an 8-bit file, refusing one whose shapes differ.
void loadEightBits(torch::nn::Module& module, const std::string& path, const std::string& what) {
  torch::serialize::InputArchive archive;
  archive.load_from(path);
  torch::NoGradGuard no_grad;
  const auto tensors = tensorsOf(module);
  for (std::size_t i = 0; i < tensors.size(); ++i) {
    const auto& [name, target] = tensors[i];
    torch::Tensor value;
    if (storedInEightBits(target)) {
      const torch::Tensor codes = readTensor(archive, eightBitKey("q", i));
      if (codes.sizes() == target.sizes()) {
        const torch::Tensor low = readTensor(archive, eightBitKey("low", i)).unsqueeze(1);
        const torch::Tensor step = readTensor(archive, eightBitKey("step", i)).unsqueeze(1);
        value = (codes.reshape({codes.size(0), -1}).to(torch::kFloat32) * step + low)
                    .reshape(target.sizes());
      } else {
        value = codes;
      }
    } else {
      value = readTensor(archive, eightBitKey("t", i));
    }
    copyStoredTensor(target, value, name, path, what);
  }
}

// Copies each tensor `archive` holds for `module` (named `prefix` + its key) into the module's
// own, converted to the module's type: a float16 file loads into float32, and a counter stays an
// integer whatever type a file stored it in. (libtorch's Module::load instead makes each tensor
// view the stored one's memory, keeping its own type: an int64 counter stored as float32 then
// read 8 bytes from 4.) Mirrors Module::save's layout: a module's parameters and buffers under
// their keys, each child in an archive of its own.
void readTensors(torch::nn::Module& module, torch::serialize::InputArchive& archive,
                 const std::string& prefix, const std::string& path, const std::string& what) {
  torch::NoGradGuard no_grad;
  const auto read = [&](const std::string& key, const torch::Tensor& target, bool is_buffer) {
    if (!target.defined()) return;  // a layer's absent bias
    torch::Tensor stored;
    if (!archive.try_read(key, stored, is_buffer) || !stored.defined()) {
      throw InvalidArgumentError("model " + path + " does not match " + what + ": it has no " +
                                 prefix + key);
    }
    copyStoredTensor(target, stored, prefix + key, path, what);
  };
  for (const auto& item : module.named_parameters(/*recurse=*/false))
    read(item.key(), item.value(), false);
  for (const auto& item : module.named_buffers(/*recurse=*/false))
    read(item.key(), item.value(), true);
  for (const auto& child : module.named_children()) {
    if (!child.value()->is_serializable()) continue;
    torch::serialize::InputArchive child_archive;
    if (!archive.try_read(child.key(), child_archive)) {
      throw InvalidArgumentError("model " + path + " does not match " + what + ": it has no " +
                                 prefix + child.key());
    }
    readTensors(*child.value(), child_archive, prefix + child.key() + ".", path, what);
  }
}

// Converts the floating-point parameters and buffers of `module` to `type`, leaving integer
// buffers (BatchNorm's counters) as they are; torch::nn::Module::to converts every tensor.
void convertFloatingTensors(torch::nn::Module& module, torch::Dtype type) {
  torch::NoGradGuard no_grad;
  for (auto& tensor : module.parameters()) {
    if (tensor.defined() && tensor.is_floating_point()) tensor.set_data(tensor.to(type));
  }
  for (auto& tensor : module.buffers()) {
    if (tensor.defined() && tensor.is_floating_point()) tensor.set_data(tensor.to(type));
  }
}

}  // namespace

void readParameters(torch::nn::Module& module, torch::serialize::InputArchive& archive,
                    const std::string& path, const std::string& what) {
  readTensors(module, archive, "", path, what);
}

void loadCheckedParameters(torch::nn::Module& module, const std::string& path,
                           const std::string& what, WeightStorage stored) {
  torch::NoGradGuard no_grad;
  try {
    if (stored == WeightStorage::kUint8) {
      loadEightBits(module, path, what);
      return;
    }
    // float32 and float16 files alike: each stored tensor is converted to the module's type.
    torch::serialize::InputArchive archive;
    archive.load_from(path);
    readParameters(module, archive, path, what);
  } catch (const c10::Error& error) {
    throw InvalidArgumentError("model " + path + " is corrupt or does not match " + what + ": " +
                               briefReason(error.what_without_backtrace()));
  }
}

void readCheckpoint(const std::string& run_dir, const std::function<void()>& read) {
  const auto refuse = [&run_dir](const char* reason) {
    return InvalidArgumentError("the checkpoint in " + run_dir + " cannot be read (" +
                                briefReason(reason) +
                                "): it is damaged or incomplete; remove its checkpoint files to "
                                "start the run again, or give another output folder");
  };
  try {
    read();
  } catch (const c10::Error& error) {
    throw refuse(error.what_without_backtrace());
  } catch (const nlohmann::json::exception& error) {
    throw refuse(error.what());
  }
}

namespace {
// The manifest's "weights" for each storage.
constexpr const char* kFloat32Weights = "float32";
constexpr const char* kFloat16Weights = "float16";
constexpr const char* kUint8Weights = "uint8";
}  // namespace

WeightStorage storedWeights(const nlohmann::json& manifest, const std::string& path) {
  const std::string weights = manifest.value("weights", std::string(kFloat32Weights));
  if (weights == kFloat32Weights) return WeightStorage::kFloat32;
  if (weights == kFloat16Weights) return WeightStorage::kFloat16;
  if (weights == kUint8Weights) return WeightStorage::kUint8;
  throw InvalidArgumentError("model " + path + ": its manifest's weights \"" + weights +
                             "\" are none of float32, float16 and uint8");
}

void saveCompactCopy(const std::string& source, const std::string& path, WeightStorage storage) {
  if (storage == WeightStorage::kFloat32) {
    throw InvalidArgumentError("compact copy: float32 is the storage of a model as trained");
  }
  LoadedModel model = loadModel(source);  // refuses a missing or broken source first
  if (std::filesystem::exists(path) && std::filesystem::equivalent(source, path)) {
    throw InvalidArgumentError("compact copy: " + path + " is the source model itself");
  }
  nlohmann::json manifest = model.manifest;
  if (storage == WeightStorage::kFloat16) {
    convertFloatingTensors(*model.network, torch::kFloat16);
    torch::save(model.network, path);
    manifest["weights"] = kFloat16Weights;
  } else {
    saveEightBits(*model.network, path);
    manifest["weights"] = kUint8Weights;
  }
  // The model it copies. A source that is itself a copy passes on its own "copy_of" (as
  // "source_copy_of") or "half_precision_of" (the key of the first float16 copies) as lineage.
  for (const char* key : {"copy_of", "copy_of_sha256"}) {
    if (!manifest.contains(key)) continue;
    manifest[std::string("source_") + key] = manifest.at(key);
    manifest.erase(key);
  }
  manifest["copy_of"] = source;
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
                        storedWeights(model.manifest, path));
  model.network->eval();
  return model;
}

}  // namespace learning
}  // namespace occlusion_env
