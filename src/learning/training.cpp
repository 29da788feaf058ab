#include "occlusion_env/learning/training.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <thread>
#include <tuple>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/statistics.hpp"
#include "occlusion_env/common/text_file.hpp"
#include "occlusion_env/dataset/bop_dataset.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/negative_frames.hpp"
#include "occlusion_env/learning/network_input.hpp"

namespace occlusion_env {
namespace learning {

// The JSON form of EpochMetrics (checkpoint state and model manifests), field by field.
// Fields a run recorded before they existed read as their defaults.
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(EpochMetrics, epoch, learning_rate, train_loss,
                                                val_dice_loss, val_pixel_accuracy, val_iou,
                                                val_gradient_mse, val_escape_mse,
                                                val_gradient_angle_deg, val_escape_angle_deg,
                                                val_escape_bins_angle_deg, seconds,
                                                images_per_second, val_escape_shortest_share,
                                                val_escape_bins_shortest_share)

namespace {

namespace fs = std::filesystem;
constexpr double kSmoothL1Beta = 0.01;

Samples emptySamples(int64_t n, const InputFormat& format) {
  const int size = format.size;
  Samples samples;
  samples.inputs = torch::empty({n, format.channels(), size, size}, torch::kHalf);
  samples.masks = torch::empty({n, 1, size, size}, torch::kUInt8);
  samples.gradient = torch::zeros({n, 2});
  samples.gradient_valid = torch::zeros({n});
  samples.escape = torch::zeros({n, 2});
  samples.escape_valid = torch::zeros({n});
  samples.oracle_steps = torch::full({n}, -1, torch::kInt);
  samples.shortest_moves = torch::zeros({n, kShortestMoveDirections}, torch::kUInt8);
  return samples;
}

// The radius of the sphere a frame was seen from [m]: its labels' drawn camera, or the
// working radius for frames recorded before labels named one (all at 4 m).
double frameRadius(const dataset::Frame& frame) {
  return frame.labels.setup ? frame.labels.setup->radius_m : kWorkingRadiusM;
}

// Writes `frames` of `data` into `samples` from row `first` on.
void fillSamples(const dataset::BopDataset& data, const std::vector<const dataset::Frame*>& frames,
                 const InputFormat& format, Samples& samples, int64_t first,
                 double mask_coverage = kPaperMaskCoverage) {
  // The area-averaged mask (0-255) must exceed this: 127 at the paper's 0.5.
  const double mask_threshold = std::max(0.0, std::floor(255.0 * mask_coverage - 0.5));
  const int size = format.size;
  const int64_t n = static_cast<int64_t>(frames.size());
  InputScratch scratch;
  const torch::Tensor input = torch::empty({format.channels(), size, size});
  cv::Mat mask_small, mask_padded;
  for (int64_t k = 0; k < n; ++k) {
    const int64_t i = first + k;
    const dataset::Frame& frame = *frames[k];
    // With the frame's intrinsics: a model whose input clears floors and walls needs them.
    writeNetworkInput(data.readRgb(frame), data.readDepthMeters(frame), frame.intrinsics,
                      format.atRadius(frameRadius(frame)), scratch, input.data_ptr<float>());
    samples.inputs[i].copy_(input);
    // The labels of the part of the view the network sees (nothing occluded beyond the image).
    const cv::Mat whole_mask = data.readOcclusionMask(frame);
    const cv::Mat mask =
        viewPart(whole_mask, seenViewRect(whole_mask.size(), frame.intrinsics, format),
                 cv::Scalar::all(0), mask_padded);
    cv::resize(mask, mask_small, cv::Size(size, size), 0, 0, cv::INTER_AREA);
    // Occluded (1) where at least mask_coverage of the pixel's area is, written into the
    // sample's bytes.
    cv::Mat mask_out(size, size, CV_8UC1, samples.masks[i].data_ptr<std::uint8_t>());
    cv::threshold(mask_small, mask_out, mask_threshold, 1, cv::THRESH_BINARY);
    const dataset::FrameLabels& labels = frame.labels;
    samples.oracle_steps[i] = labels.oracle_steps;
    if (!labels.shortest_first_moves.empty()) {
      if (labels.shortest_first_moves.size() != kShortestMoveDirections) {
        throw InvalidArgumentError(
            "dataset: a frame records " + std::to_string(labels.shortest_first_moves.size()) +
            " shortest-move directions, not " + std::to_string(kShortestMoveDirections));
      }
      std::copy(labels.shortest_first_moves.begin(), labels.shortest_first_moves.end(),
                samples.shortest_moves[i].data_ptr<std::uint8_t>());
    }
    if (labels.descent) {
      samples.gradient[i][0] = labels.descent->sin;
      samples.gradient[i][1] = labels.descent->cos;
      samples.gradient_valid[i] = 1.0;
    }
    if (labels.escape) {
      samples.escape[i][0] = labels.escape->sin;
      samples.escape[i][1] = labels.escape->cos;
      samples.escape_valid[i] = 1.0;
    }
  }
}

// Writes `count` frames with nothing to occlude into `samples` from row `first` on: even ones a
// bare surface, odd ones an object nothing hides, alone, from a training frame drawn at random
// (a bare surface when 100 draws find none). Empty masks, no direction labels.
void fillNegatives(const std::vector<std::unique_ptr<dataset::BopDataset>>& datasets,
                   const std::vector<std::vector<const dataset::Frame*>>& train,
                   const InputFormat& format, int64_t count, std::uint64_t seed, Samples& samples,
                   int64_t first) {
  if (count == 0) return;
  std::vector<std::pair<std::size_t, const dataset::Frame*>> frames;
  for (std::size_t d = 0; d < train.size(); ++d) {
    for (const dataset::Frame* frame : train[d]) frames.emplace_back(d, frame);
  }
  std::mt19937_64 random(seed * 7919ull + 17ull);
  std::uniform_int_distribution<std::size_t> pick(0, std::max<std::size_t>(1, frames.size()) - 1);
  InputScratch scratch;
  const torch::Tensor input = torch::empty({format.channels(), format.size, format.size});
  // [px] bare surfaces are drawn at the first dataset's frame size (frames are square); an object
  // alone covers at least 1 % of such a frame, enough to show what it looks like alone.
  const int surface_px = datasets.front()->manifest().at("options").at("size").get<int>();
  const int min_pixels = std::max(1, surface_px * surface_px / 100);
  int64_t alone = 0;
  for (int64_t k = 0; k < count; ++k) {
    const int64_t row = first + k;
    std::optional<CameraFrame> frame;
    double radius_m = kWorkingRadiusM;  // bare surfaces: drawn as a room's seen from the sphere
    for (int attempt = 0; k % 2 == 1 && !frames.empty() && !frame && attempt < 100; ++attempt) {
      const auto& [d, drawn] = frames[pick(random)];
      const dataset::BopDataset& data = *datasets[d];
      const std::vector<cv::Mat> masks = data.readUnoccludedObjectMasks(*drawn, min_pixels);
      if (masks.empty()) continue;  // the images are read only for a frame that has one
      CameraFrame whole;
      whole.rgb = data.readRgb(*drawn);
      whole.depth = data.readDepthMeters(*drawn);
      whole.intrinsics = drawn->intrinsics;
      radius_m = frameRadius(*drawn);
      frame = objectAloneFrame(whole, masks[random() % masks.size()]);
      ++alone;
    }
    if (!frame) frame = bareSurfaceFrame(random(), surface_px);
    writeNetworkInput(frame->rgb, frame->depth, frame->intrinsics, format.atRadius(radius_m),
                      scratch, input.data_ptr<float>());
    samples.inputs[row].copy_(input);
    samples.masks[row].zero_();
  }
  std::cerr << "training data: " << count << " frames with nothing to occlude added ("
            << count - alone << " bare surfaces, " << alone << " objects alone)\n";
}

torch::Tensor maskedMean(const torch::Tensor& values, const torch::Tensor& valid) {
  return (values * valid).sum() / valid.sum().clamp_min(1.0);
}

// Per-sample direction loss: ||p - t||^2 (Eq. 11) or SmoothL1 with beta 0.01 summed over (sin,
// cos).
torch::Tensor directionLoss(const torch::Tensor& prediction, const torch::Tensor& target,
                            const std::string& kind) {
  if (kind == "smooth_l1") {
    return torch::nn::functional::smooth_l1_loss(prediction, target,
                                                 torch::nn::functional::SmoothL1LossFuncOptions()
                                                     .reduction(torch::kNone)
                                                     .beta(kSmoothL1Beta))
        .sum(1);
  }
  return (prediction - target).pow(2).sum(1);
}

torch::Tensor softDiceLoss(const torch::Tensor& logits, const torch::Tensor& masks) {
  const torch::Tensor p = torch::sigmoid(logits);
  const torch::Tensor intersection = (p * masks).sum({1, 2, 3});
  const torch::Tensor denominator = (p * p).sum({1, 2, 3}) + (masks * masks).sum({1, 2, 3});
  return (1.0 - (2.0 * intersection + 1.0) / (denominator + 1.0)).mean();
}

// Mean angle [deg] between the normalised prediction and the target, over valid samples.
torch::Tensor angleErrors(const torch::Tensor& prediction, const torch::Tensor& target) {
  const torch::Tensor unit = prediction / prediction.norm(2, 1, true).clamp_min(1e-9);
  return torch::acos((unit * target).sum(1).clamp(-1.0, 1.0)) * (180.0 / M_PI);
}

struct Batch {
  torch::Tensor inputs, masks, gradient, gradient_valid, escape, escape_valid;
  torch::Tensor shortest_moves;  // [B, n] float 0 / 1
};

// A batch in 32-bit floats, whatever the samples are held in.
Batch batchOf(const Samples& samples, const torch::Tensor& indices) {
  return {samples.inputs.index_select(0, indices).to(torch::kFloat),
          samples.masks.index_select(0, indices).to(torch::kFloat),
          samples.gradient.index_select(0, indices),
          samples.gradient_valid.index_select(0, indices),
          samples.escape.index_select(0, indices),
          samples.escape_valid.index_select(0, indices),
          samples.shortest_moves.index_select(0, indices).to(torch::kFloat)};
}

// Colour jitter (brightness and contrast 0.8..1.2 on the RGB channels), horizontal flips with
// the label transform (sin, cos) -> (sin, -cos) (dataset/labels.hpp), moves (shiftFrames) and
// frames without depth (dropDepth), in place.
void augment(Batch& batch, double shift, double depth_dropout) {
  const int64_t n = batch.inputs.size(0);
  torch::Tensor rgb = batch.inputs.slice(1, 0, 3) * 0.25 + 0.5;
  const torch::Tensor brightness = torch::empty({n, 1, 1, 1}).uniform_(0.8, 1.2);
  const torch::Tensor contrast = torch::empty({n, 1, 1, 1}).uniform_(0.8, 1.2);
  rgb = rgb * brightness;
  const torch::Tensor mean = rgb.mean({1, 2, 3}, true);
  rgb = ((rgb - mean) * contrast + mean).clamp(0.0, 1.0);
  batch.inputs = torch::cat({(rgb - 0.5) / 0.25, batch.inputs.slice(1, 3)}, 1);  // depth (valid)

  const torch::Tensor flip = torch::rand({n}) < 0.5;
  const torch::Tensor image_flip = flip.view({n, 1, 1, 1});
  batch.inputs = torch::where(image_flip, batch.inputs.flip({3}), batch.inputs);
  batch.masks = torch::where(image_flip, batch.masks.flip({3}), batch.masks);
  const torch::Tensor sign = torch::where(flip, torch::full({n}, -1.0), torch::full({n}, 1.0));
  for (torch::Tensor* label : {&batch.gradient, &batch.escape}) {
    *label = torch::stack({label->select(1, 0), label->select(1, 1) * sign}, 1);
  }
  batch.shortest_moves = torch::where(
      flip.view({n, 1}), mirroredShortestMoves(batch.shortest_moves), batch.shortest_moves);
  shiftFrames(batch.inputs, batch.masks, shift);
  dropDepth(batch.inputs, depth_dropout);
}

void setLearningRate(torch::optim::AdamW& optimizer, double rate) {
  for (auto& group : optimizer.param_groups()) {
    static_cast<torch::optim::AdamWOptions&>(group.options()).lr(rate);
  }
}

void writeLog(const std::string& path, const std::vector<EpochMetrics>& epochs) {
  std::ostringstream out;
  out << "epoch,learning_rate,train_loss,val_dice_loss,val_pixel_accuracy,val_iou,"
         "val_gradient_mse,val_escape_mse,val_gradient_angle_deg,val_escape_angle_deg,seconds,"
         "images_per_second,val_escape_bins_angle_deg,val_escape_shortest_share,"
         "val_escape_bins_shortest_share\n";
  for (const EpochMetrics& m : epochs) {
    out << m.epoch << ',' << m.learning_rate << ',' << m.train_loss << ',' << m.val_dice_loss << ','
        << m.val_pixel_accuracy << ',' << m.val_iou << ',' << m.val_gradient_mse << ','
        << m.val_escape_mse << ',' << m.val_gradient_angle_deg << ',' << m.val_escape_angle_deg
        << ',' << m.seconds << ',' << m.images_per_second << ',' << m.val_escape_bins_angle_deg
        << ',' << m.val_escape_shortest_share << ',' << m.val_escape_bins_shortest_share << '\n';
  }
  writeTextFile(path, out.str());
}

// `path` made absolute and canonical: the same folder by another path (relative, absolute,
// through a link) gives the same string.
std::string canonicalPath(const std::string& path) {
  return fs::weakly_canonical(path).string();
}

// A run's identity with its dataset folders made absolute and canonical: the same data given by
// another path (relative, absolute, through a link) is the same data.
nlohmann::json withCanonicalPaths(nlohmann::json identity) {
  identity["dataset"] = canonicalPath(identity.at("dataset"));
  nlohmann::json& options = identity.at("options");
  if (options.contains("init_from")) options["init_from"] = canonicalPath(options["init_from"]);
  if (identity.contains("extra_datasets")) {
    for (nlohmann::json& dir : identity["extra_datasets"]) dir = canonicalPath(dir);
  }
  return identity;
}

}  // namespace

TrainingData loadTrainingData(const std::string& dir, const InputFormat& format, int max_scenes) {
  return loadTrainingData(std::vector<std::string>{dir}, format, max_scenes);
}

TrainingData loadTrainingData(const std::vector<std::string>& dirs, const InputFormat& format,
                              int max_scenes, double negatives, std::uint64_t seed,
                              double mask_coverage) {
  if (!(negatives >= 0.0 && negatives <= 1.0)) {
    throw InvalidArgumentError("negatives must be a fraction in [0, 1]");
  }
  if (!(mask_coverage > 0.0 && mask_coverage <= 1.0)) {
    throw InvalidArgumentError("mask_coverage must be a fraction in (0, 1]");
  }
  if (dirs.empty()) throw InvalidArgumentError("no dataset given");
  std::vector<std::unique_ptr<dataset::BopDataset>> datasets;
  std::vector<std::vector<const dataset::Frame*>> train(dirs.size()), validation(dirs.size());
  std::set<std::uint64_t> seeds;
  int64_t train_count = 0, validation_count = 0;
  for (std::size_t d = 0; d < dirs.size(); ++d) {
    const std::string& dir = dirs[d];
    datasets.push_back(std::make_unique<dataset::BopDataset>(dir));
    const dataset::BopDataset& data = *datasets.back();
    const nlohmann::json& options = data.manifest().at("options");
    if (options.value("model_split", "") != "train") {
      throw InvalidArgumentError("dataset " + dir +
                                 " was not made from the train split of the models: "
                                 "training on test-split models is refused");
    }
    for (const nlohmann::json& scene : data.manifest().at("scenes")) {
      const auto seed = scene.at("seed").get<std::uint64_t>();
      if (seed >= kFirstTestSeed) {
        throw InvalidArgumentError("dataset " + dir + " holds test seeds (>= " +
                                   std::to_string(kFirstTestSeed) + "): refused for training");
      }
      if (!seeds.insert(seed).second) {
        throw InvalidArgumentError("scene seed " + std::to_string(seed) + " of " + dir +
                                   " is in an earlier dataset too: use other --first-seed values");
      }
    }
    for (const dataset::Frame& frame : data.frames()) {
      if (max_scenes > 0 && frame.scene_index >= max_scenes) continue;
      (frame.validation ? validation[d] : train[d]).push_back(&frame);
    }
    train_count += static_cast<int64_t>(train[d].size());
    validation_count += static_cast<int64_t>(validation[d].size());
  }
  if (train_count == 0 || validation_count == 0) {
    throw InvalidArgumentError("no training or no validation frames in the dataset(s) from " +
                               dirs.front());
  }
  TrainingData out;
  out.dataset_manifest = datasets.front()->manifest();
  out.dataset_dir = dirs.front();
  out.extra_dataset_dirs.assign(dirs.begin() + 1, dirs.end());
  const auto negative_count =
      static_cast<int64_t>(std::llround(negatives * static_cast<double>(train_count)));
  out.train = emptySamples(train_count + negative_count, format);
  out.validation = emptySamples(validation_count, format);
  int64_t train_row = 0, validation_row = 0;
  for (std::size_t d = 0; d < dirs.size(); ++d) {
    fillSamples(*datasets[d], train[d], format, out.train, train_row, mask_coverage);
    fillSamples(*datasets[d], validation[d], format, out.validation, validation_row, mask_coverage);
    train_row += static_cast<int64_t>(train[d].size());
    validation_row += static_cast<int64_t>(validation[d].size());
  }
  fillNegatives(datasets, train, format, negative_count, seed, out.train, train_row);
  return out;
}

Samples loadCheckFrames(const std::vector<std::string>& dirs, const InputFormat& format,
                        const nlohmann::json& model_manifest, double mask_coverage,
                        std::vector<std::string>* conditions,
                        std::vector<std::uint64_t>* scene_seeds) {
  if (dirs.empty()) throw InvalidArgumentError("no dataset given");
  if (!(mask_coverage > 0.0 && mask_coverage <= 1.0)) {
    throw InvalidArgumentError("mask_coverage must be a fraction in (0, 1]");
  }
  // The model's training datasets, as recorded (paths relative to where it was trained, which
  // is where the tools run from).
  std::set<std::string> trained_on;
  if (model_manifest.contains("dataset")) {
    trained_on.insert(canonicalPath(model_manifest["dataset"]));
  }
  for (const nlohmann::json& dir :
       model_manifest.value("extra_datasets", nlohmann::json::array())) {
    trained_on.insert(canonicalPath(dir));
  }
  std::vector<std::unique_ptr<dataset::BopDataset>> datasets;
  int64_t count = 0;
  for (const std::string& dir : dirs) {
    datasets.push_back(std::make_unique<dataset::BopDataset>(dir));
    const nlohmann::json& options = datasets.back()->manifest().at("options");
    if (trained_on.count(canonicalPath(dir)) > 0 ||
        options == model_manifest.value("dataset_options", nlohmann::json())) {
      throw InvalidArgumentError("the model was trained on " + dir +
                                 ": check it on a dataset of other scenes");
    }
    count += static_cast<int64_t>(datasets.back()->frames().size());
  }
  if (count == 0) throw InvalidArgumentError("no frames in the dataset(s) from " + dirs.front());
  Samples samples = emptySamples(count, format);
  int64_t row = 0;
  for (const auto& data : datasets) {
    std::vector<const dataset::Frame*> frames;
    for (const dataset::Frame& frame : data->frames()) {
      frames.push_back(&frame);
      if (conditions) {
        const auto& setup = frame.labels.setup;
        conditions->push_back(setup ? setup->world + ", " + setup->depth_sensor : "not recorded");
      }
      if (scene_seeds) scene_seeds->push_back(frame.scene_seed);
    }
    fillSamples(*data, frames, format, samples, row, mask_coverage);
    row += static_cast<int64_t>(frames.size());
  }
  return samples;
}

void shiftFrames(torch::Tensor& inputs, torch::Tensor& masks, double shift) {
  const int64_t n = inputs.size(0), size = inputs.size(3);
  const auto reach = static_cast<int64_t>(shift * static_cast<double>(size));
  if (reach == 0) return;
  const torch::Tensor offsets = torch::randint(-reach, reach + 1, {n, 2}, torch::kLong);
  torch::Tensor moved_inputs = torch::empty_like(inputs);
  moved_inputs.slice(1, 0, 3).fill_(kBlackInput);
  moved_inputs.slice(1, 3, 4).fill_(kNoDepthInput);
  moved_inputs.slice(1, 4).fill_(kNothingReadInput);  // a valid-fraction channel, if any
  torch::Tensor moved_masks = torch::zeros_like(masks);
  using torch::indexing::Slice;
  const auto target = [size](int64_t offset) {
    return Slice(std::max<int64_t>(0, offset), size + std::min<int64_t>(0, offset));
  };
  for (int64_t i = 0; i < n; ++i) {
    const int64_t dx = offsets[i][0].item<int64_t>(), dy = offsets[i][1].item<int64_t>();
    moved_inputs.index_put_({i, Slice(), target(dy), target(dx)},
                            inputs.index({i, Slice(), target(-dy), target(-dx)}));
    moved_masks.index_put_({i, Slice(), target(dy), target(dx)},
                           masks.index({i, Slice(), target(-dy), target(-dx)}));
  }
  inputs = moved_inputs;
  masks = moved_masks;
}

void dropDepth(torch::Tensor& inputs, double probability) {
  if (probability <= 0.0) return;
  const int64_t n = inputs.size(0);
  const torch::Tensor blind = (torch::rand({n}) < probability).view({n, 1, 1, 1});
  inputs.slice(1, 3, 4).masked_fill_(blind, kNoDepthInput);
  if (inputs.size(1) > 4) inputs.slice(1, 4).masked_fill_(blind, kNothingReadInput);
}

const OptionTable<TrainingOptions>& trainingOptionTable() {
  using O = TrainingOptions;
  static const auto table =
      OptionTable<O>()
          .add("epochs", &O::epochs, OptionSpec("passes over the training frames").range(1, 10000))
          .add("batch_size", &O::batch_size,
               OptionSpec("frames per batch (>= 2: BatchNorm)").range(2, 4096).flag("--batch"))
          .add("learning_rate", &O::learning_rate,
               OptionSpec("AdamW learning rate, cosine-annealed to 0").range(1e-7, 1).flag("--lr"))
          .add("weight_decay", &O::weight_decay, OptionSpec("AdamW weight decay").range(0, 1))
          .add("direction_loss", &O::direction_loss,
               OptionSpec("loss of the direction heads (smooth_l1: beta 0.01, the paper's -L1)")
                   .choices({"mse", "smooth_l1"}))
          .add("escape_bin_concentration", &O::escape_bin_concentration,
               OptionSpec("with --escape-bins: kappa of the von Mises bump around the escape "
                          "label that the escape-bins head's cross-entropy aims at (larger: "
                          "narrower)")
                   .range(0.1, 1000))
          .add("escape_bin_targets", &O::escape_bin_targets,
               OptionSpec("with --escape-bins: what the escape-bins head's cross-entropy aims "
                          "at: label (a bump around the oracle's first move) or shortest_moves "
                          "(every first move as short as the oracle's, the middles of their "
                          "runs most, where the frames record them)")
                   .choices({"label", "shortest_moves"}))
          .add("dice_weight", &O::dice_weight, OptionSpec("beta_1 (Eq. 12)").range(0, 1000))
          .add("direction_weight", &O::direction_weight,
               OptionSpec("beta_2, for each direction head (and the escape-bins head)")
                   .range(0, 1000))
          .add("bce_weight", &O::bce_weight,
               OptionSpec("adds this times a pixel-wise binary cross-entropy on the occlusion map "
                          "to the paper's loss (0: the paper's loss)")
                   .range(0, 1000))
          .add("augment", &O::augment,
               OptionSpec("colour jitter and horizontal flips").negatedFlag("--no-augment"))
          .add("shift", &O::shift,
               OptionSpec("with augment: each frame moved by up to this fraction of its size in "
                          "x and y, labels kept, the border the void's (0: no moves)")
                   .range(0, 0.5))
          .add("depth_dropout", &O::depth_dropout,
               OptionSpec("with augment: this fraction of the training frames (drawn per batch) "
                          "read no depth anywhere, so that occlusion is learnt from colour too, as "
                          "where a sensor reads nothing nearer than its minimum range (0: none)")
                   .range(0, 1))
          .add("negatives", &O::negatives,
               OptionSpec("add this fraction of the training frames' count as frames with "
                          "nothing to occlude (empty mask, no direction labels): half bare "
                          "floors and walls, half an object nothing hides, alone (0: none)")
                   .range(0, 1))
          .add("mask_coverage", &O::mask_coverage,
               OptionSpec("a network pixel is labelled occluded where at least this fraction of "
                          "its area is occluded (0.5: the paper's masks; 0.01: any occluded "
                          "pixel); with --check, the check frames' labels")
                   .range(0.001, 1))
          .add("init_from", &O::init_from,
               OptionSpec("start from this model's weights (a best.pt of an earlier run of the "
                          "same network) instead of random ones: a new cosine schedule and a "
                          "fresh optimizer on them (a warm restart); \"\": random weights"))
          .add("seed", &O::seed, OptionSpec("weights, shuffling and augmentation"))
          .add("keep_epochs", &O::keep_epochs,
               OptionSpec("also keep every epoch's model as epoch_<k>.pt beside best.pt, to choose "
                          "one afterwards by another figure (does not change the run)"))
          .add("threads", &O::threads, OptionSpec("libtorch threads; 0 = all cores").range(0, 256));
  return table;
}

void TrainingOptions::validate() const {
  network.validate();
  trainingOptionTable().check(*this);
  if (escape_bin_targets == "shortest_moves" &&
      (network.escape_bins == 0 || kShortestMoveDirections % network.escape_bins != 0)) {
    throw InvalidArgumentError("escape_bin_targets shortest_moves needs --escape-bins dividing " +
                               std::to_string(kShortestMoveDirections));
  }
}

nlohmann::json TrainingOptions::toJson() const {
  nlohmann::json json = trainingOptionTable().toJson(*this);
  json.erase("threads");      // does not change the result
  json.erase("keep_epochs");  // nor does this
  // Only when set, so that runs from random weights keep the identity they always had.
  if (init_from.empty()) json.erase("init_from");
  if (shift == 0.0) json.erase("shift");
  if (depth_dropout == 0.0) json.erase("depth_dropout");
  if (negatives == 0.0) json.erase("negatives");
  if (mask_coverage == kPaperMaskCoverage) json.erase("mask_coverage");
  if (network.escape_bins == 0) json.erase("escape_bin_concentration");  // nothing it weighs
  // Only when it is not the bump, so that earlier runs with the bins head keep their identity.
  if (network.escape_bins == 0 || escape_bin_targets == "label") json.erase("escape_bin_targets");
  json["network"] = network.toJson();
  return json;
}

nlohmann::json EpochMetrics::toJson() const {
  return *this;
}

torch::Tensor shortestMoveTargets(const torch::Tensor& shortest_moves, int bins) {
  const int64_t directions = shortest_moves.size(1);
  if (bins <= 0 || directions % bins != 0) {
    throw InvalidArgumentError("shortest moves of " + std::to_string(directions) +
                               " directions cannot be read at " + std::to_string(bins) + " bins");
  }
  const torch::Tensor at_bins =
      shortest_moves.index_select(1, torch::arange(bins) * (directions / bins)).to(torch::kFloat);
  // Erode the runs one bin at a time: a bin's weight is how many erosions it survives.
  torch::Tensor weights = torch::zeros_like(at_bins);
  torch::Tensor kept = at_bins;
  for (int r = 0; r < (bins + 1) / 2; ++r) {
    weights = weights + kept;
    kept = kept * kept.roll(1, 1) * kept.roll(-1, 1);
  }
  return weights / weights.sum(1, true).clamp_min(1.0);
}

torch::Tensor mirroredShortestMoves(const torch::Tensor& shortest_moves) {
  const int64_t n = shortest_moves.size(1);
  return shortest_moves.index_select(1, (n / 2 - torch::arange(n) + n) % n);
}

torch::Tensor isShortestMove(const torch::Tensor& directions, const torch::Tensor& shortest_moves) {
  const int64_t n = shortest_moves.size(1);
  const torch::Tensor angles = torch::atan2(directions.select(1, 0), directions.select(1, 1));
  const torch::Tensor nearest =
      (torch::round(angles * (n / (2.0 * M_PI))).to(torch::kLong) % n + n) % n;
  return shortest_moves.gather(1, nearest.unsqueeze(1)).squeeze(1).to(torch::kFloat);
}

torch::Tensor occlusionCounts(const torch::Tensor& predicted, const torch::Tensor& masks) {
  const torch::Tensor labelled = (masks > 0.5).to(torch::kFloat);
  const torch::Tensor map = (predicted > 0.5).to(torch::kFloat);
  const torch::Tensor false_positive = map * (1.0 - labelled);
  // The label dilated by a 3 x 3 and a 7 x 7 max-pool: within 1 and 3 px (Chebyshev).
  const torch::Tensor near_1px = torch::max_pool2d(labelled, {3, 3}, {1, 1}, {1, 1});
  const torch::Tensor near_3px = torch::max_pool2d(labelled, {7, 7}, {1, 1}, {3, 3});
  const std::vector<int64_t> pixels = {1, 2, 3};
  return torch::stack(
      {(map * labelled).sum(pixels), ((map + labelled) > 0.0).sum(pixels).to(torch::kFloat),
       labelled.sum(pixels), map.sum(pixels), (false_positive * near_1px).sum(pixels),
       (false_positive * near_3px).sum(pixels)},
      1);
}

EpochMetrics evaluate(MultiTaskUNet& network, const Samples& samples, int batch_size,
                      const std::string& direction_loss, torch::Tensor* escape_errors_deg,
                      torch::Tensor* escape_shortest, torch::Tensor* occlusion_counts,
                      IouByProbability* iou_by_probability) {
  std::vector<float> sweep_logits;  // of iou_by_probability's thresholds
  std::vector<double> sweep_intersections, sweep_unions;
  if (iou_by_probability) {
    for (const double p : iou_by_probability->probabilities) {
      sweep_logits.push_back(occlusionLogit(p));
    }
    sweep_intersections.assign(sweep_logits.size(), 0.0);
    sweep_unions.assign(sweep_logits.size(), 0.0);
  }
  double escape_bins_angle = 0.0;
  double escape_shortest_count = 0.0, escape_bins_shortest_count = 0.0, shortest_count = 0.0;
  torch::NoGradGuard no_grad;
  const bool was_training = network->is_training();
  network->eval();
  double dice = 0.0, correct = 0.0, pixels = 0.0, intersection = 0.0, union_count = 0.0;
  double gradient_loss = 0.0, escape_loss = 0.0, gradient_angle = 0.0, escape_angle = 0.0;
  double gradient_count = 0.0, escape_count = 0.0;
  const int64_t n = samples.size();
  if (escape_errors_deg) *escape_errors_deg = torch::full({n}, std::nan(""));
  if (escape_shortest) *escape_shortest = torch::full({n}, std::nan(""));
  if (occlusion_counts) *occlusion_counts = torch::zeros({n, kOcclusionCounts});
  for (int64_t start = 0; start < n; start += batch_size) {
    const int64_t end = std::min<int64_t>(n, start + batch_size);
    const torch::Tensor indices = torch::arange(start, end);
    const Batch batch = batchOf(samples, indices);
    const NetworkOutput out = network->forward(batch.inputs);
    const double count = static_cast<double>(indices.size(0));
    dice += softDiceLoss(out.occlusion_logits, batch.masks).item<double>() * count;
    const torch::Tensor predicted = (out.occlusion_logits > 0.0).to(torch::kFloat);
    correct += (predicted == batch.masks).sum().item<double>();
    pixels += static_cast<double>(batch.masks.numel());
    const torch::Tensor frame_counts = occlusionCounts(predicted, batch.masks);
    intersection += frame_counts.select(1, 0).sum().item<double>();
    union_count += frame_counts.select(1, 1).sum().item<double>();
    if (!sweep_logits.empty()) {
      const torch::Tensor labelled = batch.masks > 0.5;
      for (std::size_t i = 0; i < sweep_logits.size(); ++i) {
        const torch::Tensor swept = out.occlusion_logits > sweep_logits[i];
        sweep_intersections[i] += (swept & labelled).sum().item<double>();
        sweep_unions[i] += (swept | labelled).sum().item<double>();
      }
    }
    if (occlusion_counts) occlusion_counts->slice(0, start, end).copy_(frame_counts);
    gradient_loss += (directionLoss(out.gradient_direction, batch.gradient, direction_loss) *
                      batch.gradient_valid)
                         .sum()
                         .item<double>();
    escape_loss +=
        (directionLoss(out.escape_direction, batch.escape, direction_loss) * batch.escape_valid)
            .sum()
            .item<double>();
    gradient_angle += (angleErrors(out.gradient_direction, batch.gradient) * batch.gradient_valid)
                          .sum()
                          .item<double>();
    const torch::Tensor escape_errors = angleErrors(out.escape_direction, batch.escape);
    escape_angle += (escape_errors * batch.escape_valid).sum().item<double>();
    // Frames that record shortest moves, and whether each head's move is one of them.
    const torch::Tensor recorded = (batch.shortest_moves.sum(1) > 0.0).to(torch::kFloat);
    const torch::Tensor shortest = isShortestMove(out.escape_direction, batch.shortest_moves);
    shortest_count += recorded.sum().item<double>();
    escape_shortest_count += (shortest * recorded).sum().item<double>();
    // Per frame: of the head the predicted-escape agent moves by (the bins' choice, if any).
    torch::Tensor agent_errors = escape_errors, agent_shortest = shortest;
    if (out.escape_logits.defined()) {
      const torch::Tensor chosen = escapeDirectionFromLogits(out.escape_logits);
      agent_errors = angleErrors(chosen, batch.escape);
      agent_shortest = isShortestMove(chosen, batch.shortest_moves);
      escape_bins_angle += (agent_errors * batch.escape_valid).sum().item<double>();
      escape_bins_shortest_count += (agent_shortest * recorded).sum().item<double>();
    }
    if (escape_errors_deg) {
      escape_errors_deg->slice(0, start, end)
          .copy_(torch::where(batch.escape_valid > 0.5, agent_errors,
                              torch::full_like(agent_errors, std::nan(""))));
    }
    if (escape_shortest) {
      escape_shortest->slice(0, start, end)
          .copy_(torch::where(recorded > 0.5, agent_shortest,
                              torch::full_like(agent_shortest, std::nan(""))));
    }
    gradient_count += batch.gradient_valid.sum().item<double>();
    escape_count += batch.escape_valid.sum().item<double>();
  }
  if (was_training) network->train();
  EpochMetrics m;
  m.val_dice_loss = dice / std::max<double>(1.0, n);
  m.val_pixel_accuracy = correct / std::max(1.0, pixels);
  m.val_iou = union_count > 0.0 ? intersection / union_count : 1.0;
  m.val_gradient_mse = gradient_loss / std::max(1.0, gradient_count);
  m.val_escape_mse = escape_loss / std::max(1.0, escape_count);
  m.val_gradient_angle_deg = gradient_angle / std::max(1.0, gradient_count);
  m.val_escape_angle_deg = escape_angle / std::max(1.0, escape_count);
  m.val_escape_bins_angle_deg = escape_bins_angle / std::max(1.0, escape_count);
  m.val_escape_shortest_share = escape_shortest_count / std::max(1.0, shortest_count);
  m.val_escape_bins_shortest_share = escape_bins_shortest_count / std::max(1.0, shortest_count);
  if (iou_by_probability) {
    iou_by_probability->ious.clear();
    for (std::size_t i = 0; i < sweep_logits.size(); ++i) {
      iou_by_probability->ious.push_back(
          sweep_unions[i] > 0.0 ? sweep_intersections[i] / sweep_unions[i] : 1.0);
    }
  }
  return m;
}

std::map<std::string, std::vector<int64_t>> framesByCondition(
    const std::vector<std::string>& conditions) {
  std::map<std::string, std::vector<int64_t>> frames_of;
  for (std::size_t i = 0; i < conditions.size(); ++i) {
    frames_of[conditions[i]].push_back(static_cast<int64_t>(i));
  }
  return frames_of;
}

namespace {

// The 2.5th and 97.5th percentiles of `values`.
std::pair<double, double> interval95(const std::vector<double>& values) {
  return {percentile(values, 0.025), percentile(values, 0.975)};
}

// Each scene's summed intersection and union over the rows `frames` of `counts` (evaluate()'s
// occlusion counts, one scene seed per row in `seeds`), the scenes in order of first appearance.
struct SceneSums {
  std::vector<std::uint64_t> seeds;
  std::vector<double> intersection, union_px;
};

SceneSums sumsByScene(const torch::Tensor& counts, const std::vector<std::uint64_t>& seeds,
                      const std::vector<int64_t>& frames) {
  if (static_cast<int64_t>(seeds.size()) != counts.size(0)) {
    throw InvalidArgumentError("one scene seed per frame is needed (" +
                               std::to_string(seeds.size()) + " seeds, " +
                               std::to_string(counts.size(0)) + " frames)");
  }
  const torch::Tensor rows_double = counts.to(torch::kDouble).contiguous();
  const auto rows = rows_double.accessor<double, 2>();
  SceneSums sums;
  std::map<std::uint64_t, std::size_t> scene_of_seed;
  for (const int64_t frame : frames) {
    const auto [it, added] = scene_of_seed.emplace(seeds.at(frame), sums.seeds.size());
    if (added) {
      sums.seeds.push_back(seeds.at(frame));
      sums.intersection.push_back(0.0);
      sums.union_px.push_back(0.0);
    }
    sums.intersection[it->second] += rows[frame][0];
    sums.union_px[it->second] += rows[frame][1];
  }
  return sums;
}

std::vector<int64_t> everyRow(const torch::Tensor& counts) {
  std::vector<int64_t> rows(static_cast<std::size_t>(counts.size(0)));
  std::iota(rows.begin(), rows.end(), int64_t{0});
  return rows;
}

double pooledIou(double intersection, double union_px) {
  return union_px > 0.0 ? intersection / union_px : 1.0;  // as evaluate()'s
}

}  // namespace

IouGap sceneBootstrapIouGap(const torch::Tensor& counts_a,
                            const std::vector<std::uint64_t>& seeds_a,
                            const torch::Tensor& counts_b,
                            const std::vector<std::uint64_t>& seeds_b, int draws,
                            std::uint64_t seed) {
  if (draws < 1) throw InvalidArgumentError("sceneBootstrapIouGap: draws must be >= 1");
  const SceneSums a = sumsByScene(counts_a, seeds_a, everyRow(counts_a));
  const SceneSums b = sumsByScene(counts_b, seeds_b, everyRow(counts_b));
  std::map<std::uint64_t, std::size_t> scene_in_b;
  for (std::size_t j = 0; j < b.seeds.size(); ++j) scene_in_b[b.seeds[j]] = j;
  // Per shared scene, in a's order: intersection and union in a, then in b.
  std::vector<std::array<double, 4>> shared;
  for (std::size_t i = 0; i < a.seeds.size(); ++i) {
    const auto j = scene_in_b.find(a.seeds[i]);
    if (j == scene_in_b.end()) continue;
    shared.push_back(
        {a.intersection[i], a.union_px[i], b.intersection[j->second], b.union_px[j->second]});
  }
  if (shared.empty()) {
    throw InvalidArgumentError("sceneBootstrapIouGap: the two sets hold no scene seed in common");
  }
  const auto gapOf = [](const std::array<double, 4>& total) {
    return pooledIou(total[0], total[1]) - pooledIou(total[2], total[3]);
  };
  IouGap result;
  result.scenes = static_cast<int>(shared.size());
  std::array<double, 4> total{};
  for (const auto& scene : shared) {
    for (int k = 0; k < 4; ++k) total[k] += scene[k];
  }
  result.gap = gapOf(total);
  std::mt19937_64 generator(seed);
  std::uniform_int_distribution<std::size_t> pick(0, shared.size() - 1);
  std::vector<double> gaps(static_cast<std::size_t>(draws));
  for (double& gap : gaps) {
    std::array<double, 4> drawn{};
    for (std::size_t i = 0; i < shared.size(); ++i) {
      const auto& scene = shared[pick(generator)];
      for (int k = 0; k < 4; ++k) drawn[k] += scene[k];
    }
    gap = gapOf(drawn);
  }
  std::tie(result.low, result.high) = interval95(gaps);
  return result;
}

IouInterval sceneBootstrapIou(const torch::Tensor& occlusion_counts,
                              const std::vector<std::uint64_t>& scene_seeds,
                              const std::vector<int64_t>& frames, int draws, std::uint64_t seed) {
  if (draws < 1) throw InvalidArgumentError("sceneBootstrapIou: draws must be >= 1");
  const SceneSums sums = sumsByScene(occlusion_counts, scene_seeds, frames);
  const std::vector<double>& intersection = sums.intersection;
  const std::vector<double>& union_px = sums.union_px;
  IouInterval interval;
  interval.scenes = static_cast<int>(intersection.size());
  if (intersection.empty()) return interval;
  std::mt19937_64 generator(seed);
  std::uniform_int_distribution<std::size_t> pick(0, intersection.size() - 1);
  std::vector<double> ious(static_cast<std::size_t>(draws));
  for (double& iou : ious) {
    double drawn_intersection = 0.0, drawn_union = 0.0;
    for (std::size_t i = 0; i < intersection.size(); ++i) {
      const std::size_t scene = pick(generator);
      drawn_intersection += intersection[scene];
      drawn_union += union_px[scene];
    }
    iou = pooledIou(drawn_intersection, drawn_union);
  }
  std::tie(interval.low, interval.high) = interval95(ious);
  return interval;
}

nlohmann::json figuresByCondition(const std::vector<std::string>& conditions,
                                  const torch::Tensor& occlusion_counts,
                                  const torch::Tensor& escape_errors_deg,
                                  const std::vector<std::uint64_t>& scene_seeds) {
  if (occlusion_counts.dim() != 2 || occlusion_counts.size(1) != kOcclusionCounts) {
    throw InvalidArgumentError(
        "figuresByCondition: occlusion_counts must be occlusionCounts()' [N, " +
        std::to_string(kOcclusionCounts) + "]");
  }
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& [condition, frames] : framesByCondition(conditions)) {
    const torch::Tensor index = torch::tensor(frames, torch::kLong);
    const torch::Tensor counts = occlusion_counts.index_select(0, index).sum(0);
    const double intersection_px = counts[0].item<double>();
    const double union_px = counts[1].item<double>();
    const double labelled_px = counts[2].item<double>();
    const double predicted_px = counts[3].item<double>();
    // Precision and recall say whether a condition loses its IoU to false alarms or to misses.
    nlohmann::json row = {{"condition", condition},
                          {"frames", static_cast<int64_t>(frames.size())},
                          {"val_iou", union_px > 0.0 ? intersection_px / union_px : 1.0},
                          {"labelled_px", labelled_px},
                          {"predicted_px", predicted_px},
                          {"precision", predicted_px > 0.0 ? intersection_px / predicted_px : 1.0},
                          {"recall", labelled_px > 0.0 ? intersection_px / labelled_px : 1.0}};
    const double false_positive_px = predicted_px - intersection_px;
    row["false_positive_px"] = false_positive_px;
    if (false_positive_px > 0.0) {
      row["false_positives_within_1px"] = counts[4].item<double>() / false_positive_px;
      row["false_positives_within_3px"] = counts[5].item<double>() / false_positive_px;
    }
    if (!scene_seeds.empty()) {
      const IouInterval interval = sceneBootstrapIou(occlusion_counts, scene_seeds, frames);
      row["scenes"] = interval.scenes;
      row["val_iou_95"] = {interval.low, interval.high};
    }
    const torch::Tensor errors = escape_errors_deg.index_select(0, index);
    const torch::Tensor labelled = errors.masked_select(errors.isnan().logical_not());
    if (labelled.numel() > 0) row["mean_escape_deg"] = labelled.mean().item<double>();
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json escapeErrorsByOracleSteps(const torch::Tensor& errors_deg,
                                         const torch::Tensor& oracle_steps,
                                         const torch::Tensor& shortest) {
  struct Bucket {
    const char* name;
    int first, last;  // oracle's steps, inclusive
  };
  const Bucket buckets[] = {{"1", 1, 1},        {"2", 2, 2},   {"3", 3, 3},
                            {"4-5", 4, 5},      {"6-8", 6, 8}, {"9 or more", 9, 1 << 30},
                            {"all", 1, 1 << 30}};
  const torch::Tensor labelled = errors_deg.isnan().logical_not();
  nlohmann::json rows = nlohmann::json::array();
  for (const Bucket& bucket : buckets) {
    const torch::Tensor in =
        labelled.logical_and(oracle_steps >= bucket.first).logical_and(oracle_steps <= bucket.last);
    const torch::Tensor errors = errors_deg.masked_select(in);
    const int64_t n = errors.numel();
    if (n == 0) continue;
    const auto share = [&](double above) {
      return (errors > above).sum().item<double>() / static_cast<double>(n);
    };
    rows.push_back({{"oracle_steps", bucket.name},
                    {"frames", n},
                    {"mean_deg", errors.mean().item<double>()},
                    {"median_deg", errors.median().item<double>()},
                    {"share_over_45_deg", share(45.0)},
                    {"share_over_90_deg", share(90.0)}});
    if (shortest.defined()) {
      const torch::Tensor moves = shortest.masked_select(in);
      const torch::Tensor recorded = moves.masked_select(moves.isnan().logical_not());
      if (recorded.numel() > 0) {
        rows.back()["frames_with_shortest_moves"] = recorded.numel();
        rows.back()["share_shortest"] = recorded.mean().item<double>();
      }
    }
  }
  return rows;
}

namespace {

// The manifest of the model a warm restart (--init-from) starts from; null without one. Throws
// InvalidArgumentError when that model is not a network like the one being trained.
nlohmann::json initialModelManifest(const TrainingOptions& options) {
  if (options.init_from.empty()) return nlohmann::json();
  nlohmann::json init_manifest = readManifest(options.init_from);
  // The same weights' shapes: depth_gaps and input_size may differ (a network retrained on
  // another input; the heads pool globally, so no weight depends on the size), and escape_bins
  // (the run adds or replaces that head, loadInitialWeights).
  const auto architecture = [](const NetworkConfig& network) {
    nlohmann::json json = network.toJson();
    json.erase("depth_gaps");
    json.erase("bounding_surfaces");
    json.erase("depth_reference");
    json.erase("view_crop");
    json.erase("view_field_of_view");
    json.erase("input_size");
    json.erase("escape_bins");
    return json;
  };
  if (init_manifest.value("kind", "multitask_unet") != "multitask_unet" ||
      !init_manifest.contains("network") ||
      architecture(NetworkConfig::fromJson(init_manifest.at("network"))) !=
          architecture(options.network)) {
    throw InvalidArgumentError("--init-from " + options.init_from +
                               " is not a multi-task network like the one being trained (" +
                               options.network.toJson().dump() + ")");
  }
  return init_manifest;
}

// What a checkpoint must have been made with to be resumed: the options and the data, and the
// model a warm restart started from (what it was: its manifest).
nlohmann::json runIdentity(const TrainingData& data, const TrainingOptions& options,
                           const nlohmann::json& init_manifest) {
  nlohmann::json identity = {{"options", options.toJson()},
                             {"dataset", data.dataset_dir},
                             {"dataset_options", data.dataset_manifest.at("options")},
                             {"train_frames", data.train.size()},
                             {"validation_frames", data.validation.size()}};
  if (!data.extra_dataset_dirs.empty()) identity["extra_datasets"] = data.extra_dataset_dirs;
  if (!options.init_from.empty()) identity["init_from_manifest"] = init_manifest;
  return identity;
}

// Loads options.init_from (whose manifest initialModelManifest read) into `network`. A model
// without the escape-bins head (or with another number of bins) gives every other weight, and the
// head starts from its initial weights.
void loadInitialWeights(MultiTaskUNet& network, const TrainingOptions& options,
                        const nlohmann::json& init_manifest) {
  NetworkConfig init_config = options.network;
  init_config.escape_bins = NetworkConfig::fromJson(init_manifest.at("network")).escape_bins;
  const std::string what =
      "the network being trained (" + init_config.toJson().dump() + ", escape-bins head aside)";
  const WeightStorage stored = storedWeights(init_manifest, options.init_from);
  if (init_config.escape_bins == options.network.escape_bins) {
    loadCheckedParameters(*network, options.init_from, what, stored);
    return;
  }
  MultiTaskUNet init(init_config);
  loadCheckedParameters(*init, options.init_from, what, stored);
  torch::NoGradGuard no_grad;
  const auto copy = [](const torch::OrderedDict<std::string, torch::Tensor>& from,
                       torch::OrderedDict<std::string, torch::Tensor> to) {
    for (const auto& item : from) {
      if (item.key().rfind("escape_bins_head.", 0) == 0) continue;
      to[item.key()].copy_(item.value());
    }
  };
  copy(init->named_parameters(), network->named_parameters());
  copy(init->named_buffers(), network->named_buffers());
}

// Where a run stands: the epochs done and the best validation IoU so far.
struct TrainingProgress {
  std::vector<EpochMetrics> history;
  double best_iou = -1.0;
};

// The run's files: a checkpoint (network and optimiser) and its state (identity, progress).
struct RunFiles {
  fs::path dir, checkpoint, state;
  explicit RunFiles(const std::string& run_dir)
      : dir(run_dir), checkpoint(dir / "checkpoint.pt"), state(dir / "checkpoint.json") {}
};

// Resumes from the run's checkpoint when there is one (it must have `identity`), else starts a
// warm restart from options.init_from, else from the network's initial weights.
TrainingProgress resumeOrStart(MultiTaskUNet& network, torch::optim::AdamW& optimizer,
                               const RunFiles& files, const nlohmann::json& identity,
                               const TrainingOptions& options,
                               const nlohmann::json& init_manifest) {
  TrainingProgress progress;
  if (fs::exists(files.checkpoint) && fs::exists(files.state)) {
    readCheckpoint(files.dir.string(), [&] {
      std::ifstream in(files.state);
      const nlohmann::json state = nlohmann::json::parse(in);
      if (withCanonicalPaths(state.at("identity")) != withCanonicalPaths(identity)) {
        throw InvalidArgumentError("the checkpoint in " + files.dir.string() +
                                   " was made with other options or data; use another --out "
                                   "folder");
      }
      torch::serialize::InputArchive archive;
      archive.load_from(files.checkpoint.string());
      torch::serialize::InputArchive model_archive, optimizer_archive;
      archive.read("model", model_archive);
      archive.read("optimizer", optimizer_archive);
      readParameters(*network, model_archive, files.checkpoint.string(),
                     "the network being trained");
      optimizer.load(optimizer_archive);
      for (const nlohmann::json& epoch : state.at("history"))
        progress.history.push_back(epoch.get<EpochMetrics>());
      progress.best_iou = state.at("best_iou").get<double>();
    });
  } else if (!options.init_from.empty()) {
    loadInitialWeights(network, options, init_manifest);
  }
  return progress;
}

// The loss of one batch (Eq. 10 + Eq. 11, plus the optional pixel-wise cross-entropy).
torch::Tensor batchLoss(const NetworkOutput& out, const Batch& batch,
                        const TrainingOptions& options) {
  torch::Tensor loss =
      options.dice_weight * softDiceLoss(out.occlusion_logits, batch.masks) +
      options.direction_weight *
          (maskedMean(directionLoss(out.gradient_direction, batch.gradient, options.direction_loss),
                      batch.gradient_valid) +
           maskedMean(directionLoss(out.escape_direction, batch.escape, options.direction_loss),
                      batch.escape_valid));
  if (out.escape_logits.defined()) {
    torch::Tensor targets = escapeBinTargets(batch.escape, options.network.escape_bins,
                                             options.escape_bin_concentration);
    if (options.escape_bin_targets == "shortest_moves") {
      const torch::Tensor shortest =
          shortestMoveTargets(batch.shortest_moves, options.network.escape_bins);
      targets = torch::where(shortest.sum(1, true) > 0.0, shortest, targets);
    }
    const torch::Tensor cross_entropy =
        -(targets * torch::log_softmax(out.escape_logits, 1)).sum(1);
    loss = loss + options.direction_weight * maskedMean(cross_entropy, batch.escape_valid);
  }
  if (options.bce_weight > 0.0) {  // not computed at all under the paper's loss
    loss = loss + options.bce_weight *
                      torch::binary_cross_entropy_with_logits(out.occlusion_logits, batch.masks);
  }
  return loss;
}

// One epoch of the cosine schedule over all runs' batches; the last partial batch is dropped.
// Returns the metrics of the epoch: validation figures, loss, rate and speed.
EpochMetrics trainEpoch(MultiTaskUNet& network, torch::optim::AdamW& optimizer,
                        const TrainingData& data, const TrainingOptions& options, int epoch,
                        const TrainingCallbacks& callbacks) {
  const int64_t n = data.train.size();
  const int batches = static_cast<int>(n / options.batch_size);
  const double total_batches = static_cast<double>(batches) * options.epochs;
  const auto start = std::chrono::steady_clock::now();
  torch::manual_seed(options.seed * 1000003ull + static_cast<std::uint64_t>(epoch));
  const torch::Tensor order = torch::randperm(n, torch::kLong);
  network->train();
  double loss_sum = 0.0;
  double rate = options.learning_rate;
  for (int b = 0; b < batches; ++b) {
    const double progress = ((epoch - 1) * static_cast<double>(batches) + b) / total_batches;
    rate = options.learning_rate * 0.5 * (1.0 + std::cos(M_PI * progress));
    setLearningRate(optimizer, rate);
    Batch batch =
        batchOf(data.train, order.slice(0, b * options.batch_size, (b + 1) * options.batch_size));
    if (options.augment) augment(batch, options.shift, options.depth_dropout);
    const torch::Tensor loss = batchLoss(network->forward(batch.inputs), batch, options);
    optimizer.zero_grad();
    loss.backward();
    optimizer.step();
    loss_sum += loss.item<double>();
    if (callbacks.on_batch) callbacks.on_batch(epoch, b + 1, batches);
  }
  const double train_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EpochMetrics metrics = evaluate(network, data.validation, 64, options.direction_loss);
  metrics.epoch = epoch;
  metrics.learning_rate = rate;
  metrics.train_loss = loss_sum / std::max(1, batches);
  metrics.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  metrics.images_per_second = batches * options.batch_size / train_seconds;
  return metrics;
}

// The manifest of the model after an epoch (best.pt, epoch_<k>.pt): the run, its data and the
// epoch's figures.
nlohmann::json epochModelInfo(const TrainingData& data, const TrainingOptions& options,
                              const nlohmann::json& init_manifest, const EpochMetrics& metrics) {
  nlohmann::json info = {{"training", options.toJson()},
                         {"dataset", data.dataset_dir},
                         {"dataset_options", data.dataset_manifest.at("options")},
                         {"train_frames", data.train.size()},
                         {"validation_frames", data.validation.size()},
                         {"epoch", metrics.epoch},
                         {"validation", metrics.toJson()}};
  if (!data.extra_dataset_dirs.empty()) info["extra_datasets"] = data.extra_dataset_dirs;
  if (!options.init_from.empty()) {
    info["initialised_from"] = {
        {"model", options.init_from},
        {"training", init_manifest.value("training", nlohmann::json())},
        {"epoch", init_manifest.value("epoch", 0)},
        {"validation", init_manifest.value("validation", nlohmann::json())}};
  }
  return info;
}

// Checkpoint and state, each written next to the old one and then renamed over it; the log.
void writeCheckpoint(MultiTaskUNet& network, torch::optim::AdamW& optimizer, const RunFiles& files,
                     const nlohmann::json& identity, const TrainingProgress& progress) {
  torch::serialize::OutputArchive archive, model_archive, optimizer_archive;
  network->save(model_archive);
  optimizer.save(optimizer_archive);
  archive.write("model", model_archive);
  archive.write("optimizer", optimizer_archive);
  archive.save_to(files.checkpoint.string() + ".tmp");
  fs::rename(files.checkpoint.string() + ".tmp", files.checkpoint);
  nlohmann::json state = {{"identity", identity},
                          {"best_iou", progress.best_iou},
                          {"history", nlohmann::json::array()}};
  for (const EpochMetrics& m : progress.history) state["history"].push_back(m.toJson());
  replaceTextFile(files.state.string(), state.dump(1));
  writeLog((files.dir / "log.csv").string(), progress.history);
}

}  // namespace

std::vector<EpochMetrics> train(const TrainingData& data, const TrainingOptions& options,
                                const std::string& run_dir, const TrainingCallbacks& callbacks) {
  options.validate();
  if (data.train.size() < options.batch_size) {
    throw InvalidArgumentError("fewer training frames than one batch");
  }
  const int expected_size = options.network.input_size;
  if (data.train.inputs.size(2) != expected_size) {
    throw InvalidArgumentError("the data is at " + std::to_string(data.train.inputs.size(2)) +
                               " px, the network at " + std::to_string(expected_size));
  }
  if (options.escape_bin_targets == "shortest_moves" &&
      !(data.train.shortest_moves.sum(1) > 0).any().item<bool>()) {
    throw InvalidArgumentError(
        "escape_bin_targets shortest_moves: no training frame records its shortest first moves "
        "(datasets labelled before 2026-11-29 do not: relabel them with the same command)");
  }
  setLibtorchThreads(options.threads);
  fs::create_directories(run_dir);
  const RunFiles files(run_dir);
  const nlohmann::json init_manifest = initialModelManifest(options);
  const nlohmann::json identity = runIdentity(data, options, init_manifest);

  torch::manual_seed(options.seed);
  MultiTaskUNet network(options.network);
  torch::optim::AdamW optimizer(
      network->parameters(),
      torch::optim::AdamWOptions(options.learning_rate).weight_decay(options.weight_decay));
  TrainingProgress progress =
      resumeOrStart(network, optimizer, files, identity, options, init_manifest);
  const int first_epoch = static_cast<int>(progress.history.size()) + 1;
  for (int epoch = first_epoch; epoch <= options.epochs; ++epoch) {
    const EpochMetrics metrics = trainEpoch(network, optimizer, data, options, epoch, callbacks);
    progress.history.push_back(metrics);
    if (metrics.val_iou > progress.best_iou) {
      progress.best_iou = metrics.val_iou;
      saveModel(network, (files.dir / "best.pt").string(),
                epochModelInfo(data, options, init_manifest, metrics));
    }
    if (options.keep_epochs) {
      saveModel(network, (files.dir / ("epoch_" + std::to_string(epoch) + ".pt")).string(),
                epochModelInfo(data, options, init_manifest, metrics));
    }
    writeCheckpoint(network, optimizer, files, identity, progress);
    if (callbacks.on_epoch) callbacks.on_epoch(metrics);
  }
  return progress.history;
}

std::string loadedBlasLibrary() {
  // A tiny matrix product makes sure the BLAS is loaded, then /proc/self/maps says which one.
  (void)torch::mm(torch::ones({8, 8}), torch::ones({8, 8})).sum().item<float>();
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    const auto slash = line.find('/');
    if (slash == std::string::npos) continue;
    const std::string path = line.substr(slash);
    if (path.find("libblas") != std::string::npos ||
        path.find("libopenblas") != std::string::npos) {
      std::error_code error;
      const fs::path real = fs::canonical(path, error);
      return error ? path : real.string();
    }
  }
  return "";
}

void setLibtorchThreads(int threads) {
  torch::set_num_threads(
      threads > 0 ? threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency())));
}

bool referenceBlasLoaded() {
  const std::string blas = loadedBlasLibrary();
  return blas.find("openblas") == std::string::npos && blas.find("blis") == std::string::npos &&
         blas.find("mkl") == std::string::npos && !blas.empty();
}

}  // namespace learning
}  // namespace occlusion_env
