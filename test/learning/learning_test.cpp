// The learning library: the BLAS libtorch gets, the network's shapes, a tiny training run whose
// loss falls and that resumes, the model file's errors, and the learned agents' inference.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>

#include "common/temporary_dir.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/dataset/bop_dataset.hpp"
#include "occlusion_env/dataset/generator.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/learning/inference_encoder.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/negative_frames.hpp"
#include "occlusion_env/learning/occlusion_estimator.hpp"
#include "occlusion_env/learning/training.hpp"

namespace occlusion_env {
namespace learning {
namespace {

namespace fs = std::filesystem;

TEST(LearningTest, LibtorchDoesNotRunOnTheReferenceBlas) {
  const std::string blas = loadedBlasLibrary();
  std::cout << "[learning] BLAS: " << (blas.empty() ? "(none mapped)" : blas) << "\n";
  EXPECT_FALSE(referenceBlasLoaded())
      << "libtorch's convolutions run on the reference BLAS " << blas
      << " (5-8x slower): install libopenblas0-openmp (scripts/install_deps.sh)";
}

TEST(LearningTest, EveryVariantGivesTheShapesOfItsHeads) {
  for (const std::string variant : {"unet", "r_unet", "sr_unet", "sar_unet"}) {
    NetworkConfig config;
    config.variant = variant;
    config.input_size = 32;
    MultiTaskUNet network(config);
    const NetworkOutput out = network->forward(torch::randn({2, 4, 32, 32}));
    EXPECT_EQ(out.occlusion_logits.sizes(), (std::vector<int64_t>{2, 1, 32, 32})) << variant;
    EXPECT_EQ(out.gradient_direction.sizes(), (std::vector<int64_t>{2, 2})) << variant;
    EXPECT_EQ(out.escape_direction.sizes(), (std::vector<int64_t>{2, 2})) << variant;
    EXPECT_EQ(out.features.sizes(), (std::vector<int64_t>{2, 256})) << variant;
  }
  NetworkConfig bad;
  bad.input_size = 48;  // not a multiple of 32
  EXPECT_THROW(bad.validate(), InvalidArgumentError);
  bad = {};
  bad.variant = "transformer";
  EXPECT_THROW(bad.validate(), InvalidArgumentError);
}

// The encoder prepared for inference gives the network's own features, for every variant
// (separable and dilated convolutions, residual blocks), batches of one and more, with BatchNorm
// statistics far from their initial ones; a snapshot keeps the weights it was made from.
TEST(LearningTest, TheInferenceEncoderGivesTheNetworksFeatures) {
  torch::manual_seed(5);
  for (const std::string variant : {"unet", "r_unet", "sr_unet", "sar_unet"}) {
    NetworkConfig config;
    config.variant = variant;
    config.input_size = 32;
    MultiTaskUNet network(config);
    {
      torch::NoGradGuard no_grad;
      for (auto& buffer : network->named_buffers()) {
        if (buffer.key().find("running_mean") != std::string::npos) buffer.value().normal_(0, 0.3);
        if (buffer.key().find("running_var") != std::string::npos) buffer.value().uniform_(0.5, 2);
      }
      for (auto& parameter : network->parameters())
        parameter.add_(torch::randn_like(parameter) * 0.05);
    }
    network->eval();
    const InferenceEncoder encoder(*network);
    for (const int batch : {1, 3}) {
      const torch::Tensor input = torch::randn({batch, 4, 32, 32});
      torch::Tensor expected;
      {
        torch::NoGradGuard no_grad;
        expected = network->encode(input);
      }
      const torch::Tensor features = encoder.encode(input);
      ASSERT_EQ(features.sizes(), expected.sizes()) << variant;
      EXPECT_FALSE(features.requires_grad());
      const double scale = expected.abs().max().item<double>();
      EXPECT_GT(scale, 0.1) << variant;
      EXPECT_LT((features - expected).abs().max().item<double>(), 1e-4 * scale)
          << variant << ", batch " << batch;
    }
    // A later change of the network's weights does not reach the snapshot.
    const torch::Tensor input = torch::randn({1, 4, 32, 32});
    const torch::Tensor before = encoder.encode(input);
    {
      torch::NoGradGuard no_grad;
      for (auto& parameter : network->parameters()) parameter.mul_(1.5);
    }
    if (encoder.usesOneDnn()) {
      EXPECT_TRUE(torch::equal(encoder.encode(input), before)) << variant;
    }
  }
}

// A tiny dataset of the embedded objects: `scenes` scenes from `first_seed` on, 64 px.
dataset::DatasetOptions tinyDataset(int scenes, int frames, double validation_fraction,
                                    std::uint64_t first_seed = 0) {
  dataset::DatasetOptions options;
  options.scenes = scenes;
  options.frames = frames;
  options.size = 64;
  options.validation_fraction = validation_fraction;
  options.first_seed = first_seed;
  return options;
}

// Training options for seconds of training at 32 px, one thread, no augmentation.
TrainingOptions tinyTraining(int epochs) {
  TrainingOptions options;
  options.network.input_size = 32;
  options.epochs = epochs;
  options.batch_size = 8;
  options.learning_rate = 3e-3;
  options.augment = false;
  options.threads = 1;
  return options;
}

TEST(LearningTest, TinyTrainingLowersTheLossResumesAndLoads) {
  const fs::path data_dir = temporaryDir("occlusion_env_learning_data");
  dataset::generateDataset(data_dir.string(), tinyDataset(4, 8, 0.25));
  const TrainingData data = loadTrainingData(data_dir.string(), 32);
  EXPECT_EQ(data.train.size(), 24);
  EXPECT_EQ(data.validation.size(), 8);

  const TrainingOptions options = tinyTraining(6);
  const fs::path run_dir = temporaryDir("occlusion_env_learning_run");
  // Two runs of the same command in two folders: the same result.
  const std::vector<EpochMetrics> before = train(data, options, run_dir.string() + "_probe", {});
  fs::remove_all(run_dir.string() + "_probe");
  EXPECT_LT(before.back().train_loss, before.front().train_loss) << "the loss falls";

  const auto history = train(data, options, run_dir.string(), {});
  ASSERT_EQ(history.size(), 6u);
  // Same seed, same machine, same thread count: the same run.
  EXPECT_DOUBLE_EQ(history.back().train_loss, before.back().train_loss);
  // An interrupted run (here: stopped after its third epoch) resumes where its checkpoint is and
  // ends where an uninterrupted run ends.
  const fs::path interrupted_dir = temporaryDir("occlusion_env_learning_interrupted");
  TrainingCallbacks interrupt;
  interrupt.on_epoch = [](const EpochMetrics& m) {
    if (m.epoch == 3) throw std::runtime_error("interrupted");
  };
  EXPECT_THROW(train(data, options, interrupted_dir.string(), interrupt), std::runtime_error);
  const auto continued = train(data, options, interrupted_dir.string(), {});
  ASSERT_EQ(continued.size(), 6u);
  EXPECT_NEAR(continued.back().train_loss, history.back().train_loss,
              1e-6 * std::abs(history.back().train_loss))
      << "the resumed run ends as the uninterrupted one";
  fs::remove_all(interrupted_dir);

  int epochs_seen = 0;
  TrainingCallbacks count;
  count.on_epoch = [&epochs_seen](const EpochMetrics&) { ++epochs_seen; };
  const auto resumed = train(data, options, run_dir.string(), count);
  EXPECT_EQ(epochs_seen, 0) << "a finished run resumes with nothing left to do";
  EXPECT_EQ(resumed.size(), 6u);
  TrainingData same_data_other_path = data;
  same_data_other_path.dataset_dir = (data_dir / "." / "").string();
  EXPECT_EQ(train(same_data_other_path, options, run_dir.string(), count).size(), 6u)
      << "the same data by another path resumes too";
  EXPECT_EQ(epochs_seen, 0);
  TrainingOptions other = options;
  other.learning_rate = 1e-4;
  EXPECT_THROW(train(data, other, run_dir.string(), {}), InvalidArgumentError);
  EXPECT_TRUE(fs::exists(run_dir / "log.csv"));
  // A damaged checkpoint (cut short, or its state garbled) is refused by its folder with what to
  // do, not as libtorch's or JSON's error.
  const auto expectDamagedRefused = [&](const std::string& file, const std::string& text) {
    const fs::path damaged = temporaryDir("occlusion_env_learning_damaged");
    fs::copy(run_dir, damaged, fs::copy_options::recursive);
    std::ofstream(damaged / file, std::ios::trunc) << text;
    try {
      train(data, options, damaged.string(), {});
      ADD_FAILURE() << "resumed from a damaged " << file;
    } catch (const InvalidArgumentError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("the checkpoint in " + damaged.string() + " cannot be read"),
                std::string::npos)
          << message;
    }
    fs::remove_all(damaged);
  };
  expectDamagedRefused("checkpoint.pt", "cut short");
  expectDamagedRefused("checkpoint.json", "{\"identity\": ");

  // The best model loads, and the learned agents act on an observation.
  const std::string best = (run_dir / "best.pt").string();
  LoadedModel model = loadModel(best);
  EXPECT_EQ(model.network->config().input_size, 32);
  EnvironmentOptions env_options;
  env_options.width = env_options.height = 64;
  Environment environment(env_options);
  const StepResult start = environment.reset(1000000);
  const AgentRegistry registry = learningAgents();
  for (const std::string name : {"predicted_gradient", "predicted_escape"}) {
    const auto agent = registry.make(name, {environment, best});
    const Action action = agent->act(rigObservationOf(start));
    EXPECT_NEAR(std::hypot(action.d_azimuth_rad, action.d_elevation_rad) > 0.0, 1.0, 0.0) << name;
  }

  // Missing, corrupt and mismatched files are refused, each with its reason.
  const auto expectRefused = [](const std::string& path, const std::string& words) {
    try {
      loadModel(path);
      ADD_FAILURE() << "loaded " << path;
    } catch (const InvalidArgumentError& error) {
      EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
    }
  };
  expectRefused((run_dir / "no_such.pt").string(), "does not exist");
  fs::copy_file(best, run_dir / "lonely.pt");
  expectRefused((run_dir / "lonely.pt").string(), "manifest");
  fs::copy_file(run_dir / "best.json", run_dir / "corrupt.json");
  std::ofstream(run_dir / "corrupt.pt") << "not a model";
  expectRefused((run_dir / "corrupt.pt").string(), "corrupt");
  fs::copy_file(best, run_dir / "mismatch.pt");
  {
    std::ifstream in(run_dir / "best.json");
    nlohmann::json manifest = nlohmann::json::parse(in);
    manifest["network"]["base_channels"] = 16;
    std::ofstream(run_dir / "mismatch.json") << manifest.dump();
  }
  expectRefused((run_dir / "mismatch.pt").string(), "does not match");
  fs::remove_all(run_dir);
  fs::remove_all(data_dir);
}

// Bare surfaces: drawn from the seed alone, depth in range where anything is seen and black where
// nothing is; a frame of an object alone keeps its pixels only.
TEST(LearningTest, NegativeFramesHoldNothingToOcclude) {
  const CameraFrame first = bareSurfaceFrame(3, 48), again = bareSurfaceFrame(3, 48);
  EXPECT_EQ(cv::norm(first.rgb, again.rgb, cv::NORM_INF), 0.0) << "the same seed, the same frame";
  EXPECT_GT(cv::norm(first.rgb, bareSurfaceFrame(4, 48).rgb, cv::NORM_L1), 0.0);
  int seen_frames = 0;
  for (std::uint64_t seed = 0; seed < 40; ++seed) {
    const CameraFrame frame = bareSurfaceFrame(seed, 48);
    ASSERT_EQ(frame.rgb.size(), cv::Size(48, 48));
    ASSERT_EQ(frame.depth.type(), CV_32FC1);
    int seen = 0;
    for (int row = 0; row < 48; ++row) {
      for (int column = 0; column < 48; ++column) {
        const float depth = frame.depth.at<float>(row, column);
        if (std::isnan(depth)) {
          EXPECT_EQ(frame.rgb.at<cv::Vec3b>(row, column), cv::Vec3b(0, 0, 0));
          continue;
        }
        EXPECT_GT(depth, 0.0f);
        EXPECT_LT(depth, kFarDepthM * 1.2);  // the depth noise may carry a pixel a little beyond
        ++seen;
      }
    }
    if (seen > 48 * 48 / 2) ++seen_frames;
  }
  EXPECT_GE(seen_frames, 20) << "most frames show mostly surface";

  CameraFrame scene;
  scene.rgb = cv::Mat(8, 8, CV_8UC3, cv::Scalar(10, 20, 30));
  scene.depth = cv::Mat(8, 8, CV_32FC1, 2.0f);
  cv::Mat mask = cv::Mat::zeros(8, 8, CV_8UC1);
  mask(cv::Rect(2, 2, 3, 3)) = 255;
  const CameraFrame alone = objectAloneFrame(scene, mask);
  EXPECT_EQ(cv::countNonZero(alone.depth == 2.0f), 9);
  int missing = 0;
  for (int k = 0; k < 64; ++k) missing += std::isnan(alone.depth.at<float>(k / 8, k % 8)) ? 1 : 0;
  EXPECT_EQ(missing, 64 - 9) << "NaN elsewhere";
  EXPECT_EQ(alone.rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(alone.rgb.at<cv::Vec3b>(3, 3), cv::Vec3b(10, 20, 30));
  EXPECT_THROW(objectAloneFrame(scene, cv::Mat::zeros(4, 4, CV_8UC1)), InvalidArgumentError);
}

// The label of a network pixel: occluded where at least mask_coverage of its area is; a small
// coverage labels every network pixel that holds an occluded image pixel (64 px masks into 32 px
// labels: 2 x 2 image pixels each).
TEST(LearningTest, MaskCoverageLabelsEveryNetworkPixelWithEnoughOcclusion) {
  const fs::path data_dir = temporaryDir("occlusion_env_learning_coverage");
  dataset::generateDataset(data_dir.string(), tinyDataset(4, 4, 0.25));
  const TrainingData paper = loadTrainingData(data_dir.string(), 32);
  const TrainingData any = loadTrainingData({data_dir.string()}, 32, 0, 0.0, 1, 0.01);
  const TrainingData all = loadTrainingData({data_dir.string()}, 32, 0, 0.0, 1, 1.0);
  ASSERT_EQ(any.train.size(), paper.train.size());
  // The frames' masks counted by hand: per 2 x 2 block, how many image pixels are occluded.
  const dataset::BopDataset data(data_dir.string());
  int64_t row = 0, with_any = 0, with_half = 0, with_all = 0;
  for (const dataset::Frame& frame : data.frames()) {
    if (frame.validation) continue;
    const cv::Mat mask = data.readOcclusionMask(frame);
    ASSERT_EQ(mask.rows, 64);
    const auto labels = [&](const TrainingData& d) {
      return d.train.masks[row].reshape({32, 32}).to(torch::kInt);
    };
    const torch::Tensor any_labels = labels(any), paper_labels = labels(paper),
                        all_labels = labels(all);
    const auto label_any = any_labels.accessor<int, 2>();
    const auto label_paper = paper_labels.accessor<int, 2>();
    const auto label_all = all_labels.accessor<int, 2>();
    for (int r = 0; r < 32; ++r) {
      for (int c = 0; c < 32; ++c) {
        const int occluded = cv::countNonZero(mask(cv::Rect(2 * c, 2 * r, 2, 2)));
        EXPECT_EQ(label_any[r][c], occluded >= 1 ? 1 : 0)
            << "frame " << row << " at " << r << ", " << c;
        EXPECT_EQ(label_paper[r][c], occluded >= 2 ? 1 : 0) << "frame " << row;
        EXPECT_EQ(label_all[r][c], occluded == 4 ? 1 : 0) << "frame " << row;
        with_any += occluded >= 1;
        with_half += occluded >= 2;
        with_all += occluded == 4;
      }
    }
    ++row;
  }
  ASSERT_EQ(row, paper.train.size());
  EXPECT_GT(with_any, with_half) << "no occlusion edge in the data: the test checks nothing";
  EXPECT_GT(with_half, with_all);
  EXPECT_THROW(loadTrainingData({data_dir.string()}, 32, 0, 0.0, 1, 0.0), InvalidArgumentError);
  TrainingOptions options;
  EXPECT_FALSE(options.toJson().contains("mask_coverage"))
      << "the paper's runs keep their identity";
  options.mask_coverage = 0.01;
  EXPECT_DOUBLE_EQ(options.toJson().at("mask_coverage").get<double>(), 0.01);
  fs::remove_all(data_dir);
}

// Negatives are appended to the training frames only, with empty masks and no direction labels,
// the same for the same seed; objects alone come from frames of the data.
TEST(LearningTest, NegativesAreAddedTrainingFramesWithEmptyMasks) {
  const fs::path data_dir = temporaryDir("occlusion_env_learning_negatives");
  dataset::generateDataset(data_dir.string(), tinyDataset(4, 4, 0.25));
  const TrainingData plain = loadTrainingData(data_dir.string(), 32);
  const TrainingData with = loadTrainingData({data_dir.string()}, 32, 0, 0.5, 7);
  const int64_t n = plain.train.size(), added = (n + 1) / 2;
  ASSERT_EQ(with.train.size(), n + added);
  EXPECT_EQ(with.validation.size(), plain.validation.size());
  EXPECT_TRUE(torch::equal(with.train.inputs.slice(0, 0, n), plain.train.inputs));
  EXPECT_EQ(with.train.masks.slice(0, n).sum().item<int64_t>(), 0) << "nothing to occlude";
  EXPECT_EQ(with.train.escape_valid.slice(0, n).sum().item<float>(), 0.0f);
  EXPECT_EQ(with.train.gradient_valid.slice(0, n).sum().item<float>(), 0.0f);
  const TrainingData again = loadTrainingData({data_dir.string()}, 32, 0, 0.5, 7);
  EXPECT_TRUE(torch::equal(again.train.inputs, with.train.inputs));
  // An object alone: black (-2 after normalisation) around it, something in front of the void.
  const torch::Tensor alone = with.train.inputs[n + 1].to(torch::kFloat);
  EXPECT_GT((alone.slice(0, 0, 3) == -2.0).sum().item<int64_t>(), 0);
  EXPECT_GT((alone.slice(0, 0, 3) > -2.0).sum().item<int64_t>(), 0);
  EXPECT_THROW(loadTrainingData({data_dir.string()}, 32, 0, 1.5, 7), InvalidArgumentError);
  // A run records them (its identity: resuming with another fraction is another run).
  TrainingOptions options;
  EXPECT_FALSE(options.toJson().contains("negatives")) << "runs without them keep their identity";
  options.negatives = 0.2;
  EXPECT_DOUBLE_EQ(options.toJson().at("negatives").get<double>(), 0.2);
  fs::remove_all(data_dir);
}

// A second dataset without oracle labels and without validation scenes adds training frames only;
// a dataset repeating a scene seed is refused; the cross-entropy term trains too.
TEST(LearningTest, SeveralDatasetsAddTrainingFramesOnly) {
  const fs::path labelled = temporaryDir("occlusion_env_learning_labelled");
  const fs::path extra = temporaryDir("occlusion_env_learning_extra");
  dataset::generateDataset(labelled.string(), tinyDataset(4, 4, 0.25));
  dataset::DatasetOptions unlabelled = tinyDataset(4, 4, 0.0, 4);
  unlabelled.oracle_labels = false;
  dataset::generateDataset(extra.string(), unlabelled);

  const TrainingData one = loadTrainingData(labelled.string(), 32);
  const TrainingData both = loadTrainingData({labelled.string(), extra.string()}, 32);
  EXPECT_EQ(both.train.size(), one.train.size() + 16);
  EXPECT_EQ(both.validation.size(), one.validation.size());
  EXPECT_TRUE(torch::equal(both.validation.inputs, one.validation.inputs));
  EXPECT_TRUE(torch::equal(both.train.inputs.slice(0, 0, one.train.size()), one.train.inputs));
  EXPECT_EQ(both.train.escape_valid.slice(0, one.train.size()).sum().item<float>(), 0.0f)
      << "no escape labels without the oracle";
  EXPECT_EQ(both.extra_dataset_dirs, std::vector<std::string>{extra.string()});
  EXPECT_THROW(loadTrainingData({labelled.string(), labelled.string()}, 32), InvalidArgumentError)
      << "the same scene seeds twice";

  TrainingOptions training = tinyTraining(4);
  training.bce_weight = 1.0;
  const fs::path run_dir = temporaryDir("occlusion_env_learning_bce_run");
  const auto history = train(both, training, run_dir.string(), {});
  EXPECT_LT(history.back().train_loss, history.front().train_loss) << "the loss falls";
  std::ifstream manifest_file(run_dir / "best.json");
  const nlohmann::json manifest = nlohmann::json::parse(manifest_file);
  EXPECT_EQ(manifest.at("training").at("bce_weight").get<double>(), 1.0);
  EXPECT_EQ(manifest.at("extra_datasets").at(0).get<std::string>(), extra.string());
  EXPECT_EQ(manifest.at("train_frames").get<int64_t>(), both.train.size());
  fs::remove_all(run_dir);
  fs::remove_all(labelled);
  fs::remove_all(extra);
}

// The largest difference between the parameters of two saved models of the same network.
double largestParameterDifference(const std::string& a, const std::string& b) {
  const LoadedModel first = loadModel(a), second = loadModel(b);
  const auto other = second.network->named_parameters();
  double largest = 0.0;
  for (const auto& item : first.network->named_parameters()) {
    largest = std::max(largest, (item.value() - other[item.key()]).abs().max().item<double>());
  }
  return largest;
}

// A tiny dataset (4 scenes of 4 frames, at 32 px) and a model trained on it for `epochs`, each
// in a temporary folder named after `tag`: the start of a warm restart.
struct WarmStart {
  fs::path data_dir, source_dir;
  TrainingData data;
  std::string source;  // the model file
};

WarmStart warmStart(const std::string& tag, int epochs) {
  WarmStart start;
  start.data_dir = temporaryDir("occlusion_env_learning_" + tag + "_data");
  dataset::generateDataset(start.data_dir.string(), tinyDataset(4, 4, 0.25));
  start.data = loadTrainingData(start.data_dir.string(), 32);
  start.source_dir = temporaryDir("occlusion_env_learning_" + tag + "_source");
  train(start.data, tinyTraining(epochs), start.source_dir.string(), {});
  start.source = (start.source_dir / "best.pt").string();
  return start;
}

// --init-from: a run starts from the given model's weights (a warm restart; also from a float16
// copy), records it, refuses a model of another network, and resumes only with the same starting
// model.
TEST(LearningTest, WarmRestartStartsFromTheGivenModel) {
  const WarmStart start = warmStart("warm", 3);
  const fs::path &data_dir = start.data_dir, &source_dir = start.source_dir;
  const TrainingData& data = start.data;
  const std::string& source = start.source;

  // With a vanishing learning rate the weights stay where they started: at the source's with
  // --init-from, at random ones without.
  TrainingOptions still = tinyTraining(1);
  still.learning_rate = 1e-7;
  still.seed = 2;
  const fs::path fresh_dir = temporaryDir("occlusion_env_learning_warm_fresh");
  train(data, still, fresh_dir.string(), {});
  EXPECT_GT(largestParameterDifference(source, (fresh_dir / "best.pt").string()), 1e-2);
  TrainingOptions warm = still;
  warm.init_from = source;
  const fs::path warm_dir = temporaryDir("occlusion_env_learning_warm_run");
  train(data, warm, warm_dir.string(), {});
  EXPECT_LT(largestParameterDifference(source, (warm_dir / "best.pt").string()), 1e-5);
  std::ifstream manifest_file(warm_dir / "best.json");
  const nlohmann::json manifest = nlohmann::json::parse(manifest_file);
  EXPECT_EQ(manifest.at("initialised_from").at("model").get<std::string>(), source);
  EXPECT_EQ(manifest.at("training").at("init_from").get<std::string>(), source);
  EXPECT_EQ(manifest.at("initialised_from").at("epoch").get<int>(),
            loadModel(source).manifest.at("epoch").get<int>());

  // From a float16 copy of the source: the source's weights to within float16's rounding.
  const std::string half_source = (source_dir / "half.pt").string();
  saveCompactCopy(source, half_source, WeightStorage::kFloat16);
  TrainingOptions from_half = still;
  from_half.init_from = half_source;
  const fs::path half_dir = temporaryDir("occlusion_env_learning_warm_half");
  train(data, from_half, half_dir.string(), {});
  EXPECT_LT(largestParameterDifference(source, (half_dir / "best.pt").string()), 2e-3);
  // And from an 8-bit copy: within half a code's step of them.
  const std::string eight_bit_source = (source_dir / "eight_bit.pt").string();
  saveCompactCopy(source, eight_bit_source, WeightStorage::kUint8);
  TrainingOptions from_eight_bits = still;
  from_eight_bits.init_from = eight_bit_source;
  const fs::path eight_bit_dir = temporaryDir("occlusion_env_learning_warm_eight_bit");
  train(data, from_eight_bits, eight_bit_dir.string(), {});
  EXPECT_LT(largestParameterDifference(source, (eight_bit_dir / "best.pt").string()), 1e-2);

  // Resuming needs the same starting model; a model of another network is refused.
  TrainingOptions other_start = warm;
  other_start.init_from = (fresh_dir / "best.pt").string();
  EXPECT_THROW(train(data, other_start, warm_dir.string(), {}), InvalidArgumentError);
  TrainingOptions wider = warm;
  wider.network.base_channels = 16;
  const fs::path refused_dir = temporaryDir("occlusion_env_learning_warm_refused");
  EXPECT_THROW(train(data, wider, refused_dir.string(), {}), InvalidArgumentError);
  TrainingOptions missing = warm;
  missing.init_from = (source_dir / "no_such.pt").string();
  EXPECT_THROW(train(data, missing, refused_dir.string(), {}), InvalidArgumentError);
  // A model of another input size starts a run at this one: no weight depends on the size.
  TrainingOptions larger = warm;
  larger.network.input_size = 64;
  const fs::path larger_dir = temporaryDir("occlusion_env_learning_warm_larger");
  train(loadTrainingData(data_dir.string(), 64), larger, larger_dir.string(), {});
  EXPECT_LT(largestParameterDifference(source, (larger_dir / "best.pt").string()), 1e-5);
  for (const fs::path& dir :
       {data_dir, source_dir, fresh_dir, warm_dir, half_dir, refused_dir, larger_dir}) {
    fs::remove_all(dir);
  }
}

// The escape-bins head: its targets peak at the label's bin, its choice is one mode of two (not
// their mean), a run adds it to a model without one (every other weight kept), and the
// predicted-escape agent of such a model moves along the head's choice.
TEST(LearningTest, AnEscapeBinsHeadChoosesAModeAndStartsFromAModelWithoutOne) {
  constexpr int kBins = 16;
  const double label = escapeBinAngleRad(5, kBins);
  const torch::Tensor targets = escapeBinTargets(
      torch::tensor({{static_cast<float>(std::sin(label)), static_cast<float>(std::cos(label))}}),
      kBins, 8.0);
  EXPECT_EQ(targets.argmax(1).item<int64_t>(), 5);
  EXPECT_NEAR(targets.sum().item<double>(), 1.0, 1e-5);
  EXPECT_NEAR(targets[0][4].item<double>(), targets[0][6].item<double>(), 1e-6);

  // Two modes, bins 2 and 10 (opposite); bin 2 a little likelier, its neighbours alike.
  torch::Tensor logits = torch::full({1, kBins}, -10.0);
  logits[0][2] = 3.0;
  logits[0][10] = 2.9;
  logits[0][1] = logits[0][3] = 1.0;
  const torch::Tensor direction = escapeDirectionFromLogits(logits);
  const double chosen = std::atan2(direction[0][0].item<double>(), direction[0][1].item<double>());
  EXPECT_NEAR(chosen, escapeBinAngleRad(2, kBins), 1e-5);
  EXPECT_NEAR(direction.norm().item<double>(), 1.0, 1e-5);
  // A bias towards the other mode (as the agent's last move gives) chooses it.
  const torch::Tensor bias = torch::zeros({1, kBins});
  bias[0][10] = 0.5;
  const torch::Tensor biased = escapeDirectionFromLogits(logits, bias);
  EXPECT_NEAR(std::atan2(biased[0][0].item<double>(), biased[0][1].item<double>()),
              escapeBinAngleRad(10, kBins) - 2.0 * M_PI, 1e-5);
  logits[0][3] = 2.0;  // the neighbour on one side likelier: the choice leans towards it
  const torch::Tensor leaning = escapeDirectionFromLogits(logits);
  const double leaned = std::atan2(leaning[0][0].item<double>(), leaning[0][1].item<double>());
  EXPECT_GT(leaned, escapeBinAngleRad(2, kBins));
  EXPECT_LT(leaned, escapeBinAngleRad(3, kBins));

  // Networks recorded before the head existed have none; the field is written only with it.
  NetworkConfig config;
  nlohmann::json json = config.toJson();
  EXPECT_FALSE(json.contains("escape_bins"));
  EXPECT_EQ(NetworkConfig::fromJson(json).escape_bins, 0);
  config.escape_bins = kBins;
  EXPECT_EQ(NetworkConfig::fromJson(config.toJson()).escape_bins, kBins);

  const WarmStart warm = warmStart("bins", 1);
  const TrainingData& data = warm.data;
  const std::string& source = warm.source;
  TrainingOptions with_bins = tinyTraining(1);
  with_bins.network.escape_bins = kBins;
  with_bins.learning_rate = 1e-7;
  with_bins.init_from = source;
  const fs::path run_dir = temporaryDir("occlusion_env_learning_bins_run");
  const std::vector<EpochMetrics> epochs = train(data, with_bins, run_dir.string(), {});
  ASSERT_EQ(epochs.size(), 1u);
  EXPECT_GT(epochs[0].val_escape_bins_angle_deg, 0.0);
  const std::string best = (run_dir / "best.pt").string();
  EXPECT_LT(largestParameterDifference(source, best), 1e-5);
  LoadedModel model = loadModel(best);
  ASSERT_TRUE(model.network->escapeBinsHead());
  EXPECT_EQ(model.network->config().escape_bins, kBins);

  EnvironmentOptions env_options;
  env_options.width = env_options.height = 64;
  Environment environment(env_options);
  const StepResult start = environment.reset(1000000);
  const auto agent = learningAgents().make("predicted_escape", {environment, best});
  const Action action = agent->act(rigObservationOf(start));
  torch::Tensor input = torch::empty({1, 4, 32, 32});
  InputScratch scratch;
  writeNetworkInput(start.observation->rgb, start.observation->depth,
                    model.network->config().inputFormat(), scratch, input.data_ptr<float>());
  torch::NoGradGuard no_grad;
  model.network->eval();
  const torch::Tensor expected = escapeDirectionFromLogits(
      model.network->escapeBinsHead()->forward(model.network->encode(input)));
  EXPECT_NEAR(action.d_elevation_rad, expected[0][0].item<double>(), 1e-5);
  EXPECT_NEAR(action.d_azimuth_rad, expected[0][1].item<double>(), 1e-5);
  for (const fs::path& dir : {warm.data_dir, warm.source_dir, run_dir}) fs::remove_all(dir);
}

// keep_epochs keeps each epoch's model with its manifest; it does not change the run, so a run
// with it resumes one without it and ends with the same weights.
TEST(LearningTest, KeptEpochsAreEachEpochsModel) {
  const fs::path data_dir = temporaryDir("occlusion_env_learning_epochs_data");
  dataset::generateDataset(data_dir.string(), tinyDataset(4, 4, 0.25));
  const TrainingData data = loadTrainingData(data_dir.string(), 32);
  const fs::path plain_dir = temporaryDir("occlusion_env_learning_epochs_plain");
  const auto plain = train(data, tinyTraining(3), plain_dir.string(), {});
  EXPECT_FALSE(fs::exists(plain_dir / "epoch_1.pt"));

  TrainingOptions keeping = tinyTraining(3);
  keeping.keep_epochs = true;
  const fs::path kept_dir = temporaryDir("occlusion_env_learning_epochs_kept");
  TrainingCallbacks interrupt;
  interrupt.on_epoch = [](const EpochMetrics& m) {
    if (m.epoch == 2) throw std::runtime_error("interrupted");
  };
  EXPECT_THROW(train(data, tinyTraining(3), kept_dir.string(), interrupt), std::runtime_error);
  const auto kept = train(data, keeping, kept_dir.string(), {});  // resumes the run without it
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_NEAR(kept.back().train_loss, plain.back().train_loss,
              1e-6 * std::abs(plain.back().train_loss));
  EXPECT_FALSE(fs::exists(kept_dir / "epoch_2.pt")) << "epochs before it are not made up";
  const std::string last = (kept_dir / "epoch_3.pt").string();
  ASSERT_TRUE(fs::exists(last));
  EXPECT_EQ(loadModel(last).manifest.at("epoch").get<int>(), 3);
  EXPECT_DOUBLE_EQ(loadModel(last).manifest.at("validation").at("val_iou").get<double>(),
                   kept.back().val_iou);
  EXPECT_FALSE(loadModel(last).manifest.at("training").contains("keep_epochs"))
      << "not part of what the run is";
  // The best epoch's file holds best.pt's weights.
  int best_epoch = 1;
  for (const EpochMetrics& m : kept) {
    if (m.val_iou > kept[best_epoch - 1].val_iou) best_epoch = m.epoch;
  }
  if (best_epoch == 3) {
    EXPECT_LT(largestParameterDifference(last, (kept_dir / "best.pt").string()), 1e-12);
  } else {
    EXPECT_GT(largestParameterDifference(last, (kept_dir / "best.pt").string()), 0.0);
  }
  for (const fs::path& dir : {data_dir, plain_dir, kept_dir}) fs::remove_all(dir);
}

// A model is checked on every frame of other scenes than it was trained on; its own datasets are
// refused.
TEST(LearningTest, ChecksRunOnOtherScenesOnly) {
  const fs::path data_dir = temporaryDir("occlusion_env_learning_check_data");
  const fs::path other_dir = temporaryDir("occlusion_env_learning_check_other");
  dataset::generateDataset(data_dir.string(), tinyDataset(4, 4, 0.25));
  dataset::generateDataset(other_dir.string(), tinyDataset(2, 4, 0.0, 100));
  const fs::path run_dir = temporaryDir("occlusion_env_learning_check_run");
  train(loadTrainingData(data_dir.string(), 32), tinyTraining(1), run_dir.string(), {});
  LoadedModel model = loadModel((run_dir / "best.pt").string());

  EXPECT_THROW(loadCheckFrames({data_dir.string()}, 32, model.manifest), InvalidArgumentError);
  EXPECT_THROW(loadCheckFrames({other_dir.string(), (data_dir / ".").string()}, 32, model.manifest),
               InvalidArgumentError)
      << "the training data by another path";
  const Samples frames = loadCheckFrames({other_dir.string()}, 32, model.manifest);
  EXPECT_EQ(frames.size(), 8) << "every frame, whatever its split";
  // Labels at another coverage: any occluded part of a network pixel marks it.
  const Samples any_part = loadCheckFrames({other_dir.string()}, 32, model.manifest, 0.01);
  EXPECT_GT(any_part.masks.sum().item<int64_t>(), frames.masks.sum().item<int64_t>());
  EXPECT_THROW(loadCheckFrames({other_dir.string()}, 32, model.manifest, 0.0),
               InvalidArgumentError);
  torch::Tensor errors;
  const EpochMetrics figures = evaluate(model.network, frames, 4, "mse", &errors);
  EXPECT_GE(figures.val_iou, 0.0);
  EXPECT_LE(figures.val_iou, 1.0);
  EXPECT_GT(figures.val_pixel_accuracy, 0.5);
  // Each frame's error beside its label's steps: labelled frames are 1 step or more away.
  ASSERT_EQ(errors.size(0), frames.size());
  for (int64_t i = 0; i < frames.size(); ++i) {
    const bool labelled = frames.escape_valid[i].item<float>() > 0.5f;
    EXPECT_EQ(std::isnan(errors[i].item<float>()), !labelled) << "frame " << i;
    if (labelled) {
      EXPECT_GE(frames.oracle_steps[i].item<int>(), 1) << "frame " << i;
    }
  }
  for (const fs::path& dir : {data_dir, other_dir, run_dir}) fs::remove_all(dir);
}

// The IoU by probability threshold: at 0.5 it is evaluate()'s; at a probability near 0 every
// pixel is predicted, so it is the labelled share of the pixels; at one near 1 nothing is, so
// it is 0; a probability outside (0, 1) is refused.
TEST(LearningTest, IouByProbabilityMatchesEvaluateAtOneHalf) {
  const fs::path data_dir = temporaryDir("occlusion_env_learning_iou_by_probability");
  dataset::DatasetOptions options = tinyDataset(2, 3, 0.0);
  options.oracle_labels = false;
  dataset::generateDataset(data_dir.string(), options);
  const Samples frames = loadCheckFrames({data_dir.string()}, 32, nlohmann::json::object());
  ASSERT_GT(frames.masks.sum().item<double>(), 0.0) << "the tiny scenes have occlusion";
  torch::manual_seed(5);
  NetworkConfig config;
  config.input_size = 32;
  MultiTaskUNet network(config);
  IouByProbability by_probability{{1e-6, 0.5, 1.0 - 1e-6}, {}};
  const EpochMetrics m =
      evaluate(network, frames, 4, "mse", nullptr, nullptr, nullptr, &by_probability);
  const std::vector<double>& ious = by_probability.ious;
  ASSERT_EQ(ious.size(), 3u);
  EXPECT_NEAR(ious[1], m.val_iou, 1e-9);
  EXPECT_NEAR(ious[0], frames.masks.sum().item<double>() / frames.masks.numel(), 1e-9);
  EXPECT_EQ(ious[2], 0.0);
  for (const double outside : {0.0, 1.0}) {
    IouByProbability bad{{outside}, {}};
    EXPECT_THROW(evaluate(network, frames, 4, "mse", nullptr, nullptr, nullptr, &bad),
                 InvalidArgumentError);
  }
  fs::remove_all(data_dir);
}

// A check's frames are named by the world and depth sensor they were seen under, row by row, and
// evaluate()'s per-frame counts give each condition's IoU (and all of them the whole IoU).
TEST(LearningTest, CheckFramesAreNamedByTheirWorldAndDepthSensor) {
  const fs::path void_dir = temporaryDir("occlusion_env_learning_conditions_void");
  const fs::path room_dir = temporaryDir("occlusion_env_learning_conditions_room");
  dataset::DatasetOptions void_ideal = tinyDataset(1, 2, 0.0);
  void_ideal.oracle_labels = false;
  dataset::generateDataset(void_dir.string(), void_ideal);
  dataset::DatasetOptions room_d435 = tinyDataset(1, 3, 0.0, 10);
  room_d435.oracle_labels = false;
  room_d435.world = "room";
  room_d435.depth_sensor = "realsense_d435";
  dataset::generateDataset(room_dir.string(), room_d435);

  const std::vector<std::string> dirs = {void_dir.string(), room_dir.string()};
  std::vector<std::string> conditions;
  std::vector<std::uint64_t> seeds;
  const Samples frames =
      loadCheckFrames(dirs, 32, nlohmann::json::object(), kPaperMaskCoverage, &conditions, &seeds);
  ASSERT_EQ(frames.size(), 5);
  EXPECT_EQ(seeds, (std::vector<std::uint64_t>{0, 0, 10, 10, 10}));
  EXPECT_EQ(conditions,
            (std::vector<std::string>{"void, ideal", "void, ideal", "room, realsense_d435",
                                      "room, realsense_d435", "room, realsense_d435"}));

  torch::manual_seed(3);
  NetworkConfig config;
  config.input_size = 32;
  MultiTaskUNet network(config);
  torch::Tensor errors, counts;
  const EpochMetrics all = evaluate(network, frames, 2, "mse", &errors, nullptr, &counts);
  ASSERT_EQ(counts.size(0), 5);
  EXPECT_NEAR(counts.select(1, 0).sum().item<double>() / counts.select(1, 1).sum().item<double>(),
              all.val_iou, 1e-9);
  const nlohmann::json rows = figuresByCondition(conditions, counts, errors, seeds);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["scenes"], 1);  // the room's one scene: its interval is its IoU
  EXPECT_NEAR(rows[0]["val_iou_95"][0].get<double>(), rows[0]["val_iou"].get<double>(), 1e-9);
  EXPECT_NEAR(rows[0]["val_iou_95"][1].get<double>(), rows[0]["val_iou"].get<double>(), 1e-9);
  EXPECT_EQ(rows[0]["condition"], "room, realsense_d435");  // in name order
  EXPECT_EQ(rows[0]["frames"], 3);
  EXPECT_EQ(rows[1]["condition"], "void, ideal");
  EXPECT_EQ(rows[1]["frames"], 2);
  // Each row's IoU is its own frames' alone.
  Samples room = frames;
  for (torch::Tensor* field :
       {&room.inputs, &room.masks, &room.gradient, &room.gradient_valid, &room.escape,
        &room.escape_valid, &room.oracle_steps, &room.shortest_moves}) {
    *field = field->slice(0, 2, 5);
  }
  EXPECT_NEAR(rows[0]["val_iou"].get<double>(), evaluate(network, room, 2, "mse").val_iou, 1e-6);
  // Its label's pixels are its frames' masks; the map's pixels, precision and recall agree
  // with the IoU: intersection / (labelled + predicted - intersection).
  const double labelled = rows[0]["labelled_px"].get<double>();
  const double predicted = rows[0]["predicted_px"].get<double>();
  EXPECT_NEAR(labelled, room.masks.sum().item<double>(), 1e-6);
  const double intersection = rows[0]["recall"].get<double>() * labelled;
  EXPECT_NEAR(rows[0]["precision"].get<double>() * predicted, intersection, 1e-6);
  EXPECT_NEAR(rows[0]["val_iou"].get<double>(),
              intersection / (labelled + predicted - intersection), 1e-6);
  EXPECT_FALSE(rows[0].contains("mean_escape_deg")) << "no oracle labels, no escape error";
  for (const fs::path& dir : {void_dir, room_dir}) fs::remove_all(dir);
}

// The counts behind the IoU, precision and recall, and the false positives by their distance to
// the label: next to it (a fattened mask) or apart from it.
TEST(LearningTest, OcclusionCountsSortFalsePositivesByTheirDistanceToTheLabel) {
  torch::Tensor label = torch::zeros({2, 1, 16, 16});
  label.index_put_({0, 0, torch::indexing::Slice(4, 8), torch::indexing::Slice(4, 8)}, 1.0);
  torch::Tensor map = label.clone();
  map.index_put_({0, 0, 3, 5}, 1.0);    // next to the label: 1 px (above its top row)
  map.index_put_({0, 0, 5, 10}, 1.0);   // 3 px right of its last column
  map.index_put_({0, 0, 14, 14}, 1.0);  // 7 px away
  map.index_put_({0, 0, 4, 4}, 0.0);    // a miss
  map.index_put_({1, 0, 0, 0}, 1.0);    // frame 1: no label, one false alarm
  const torch::Tensor counts = occlusionCounts(map, label);
  ASSERT_EQ(counts.sizes(), (torch::IntArrayRef{2, kOcclusionCounts}));
  const std::vector<double> expected[] = {{15, 19, 16, 18, 1, 2}, {0, 1, 0, 1, 0, 0}};
  for (int frame = 0; frame < 2; ++frame) {
    for (int k = 0; k < kOcclusionCounts; ++k) {
      EXPECT_EQ(counts[frame][k].item<double>(), expected[frame][k]) << frame << ", " << k;
    }
  }
  const nlohmann::json rows =
      figuresByCondition({"a", "a"}, counts, torch::full({2}, std::nan("")));
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0]["false_positive_px"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(rows[0]["false_positives_within_1px"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(rows[0]["false_positives_within_3px"].get<double>(), 0.5);
  // Counts without the false alarms' columns (an older layout) are refused, not misread.
  EXPECT_THROW(figuresByCondition({"a", "a"}, counts.slice(1, 0, 4), torch::full({2}, 0.0)),
               InvalidArgumentError);
}

// The IoU's interval draws scenes, not frames: frames of one scene move together.
TEST(LearningTest, TheIousIntervalDrawsWholeScenes) {
  // Four scenes of two frames each: in every scene one frame is all hit (10 / 10) and one all
  // missed (0 / 10), so every scene's own IoU is 0.5 and no draw of whole scenes moves it; a
  // draw of frames would.
  const torch::Tensor halves = torch::tensor({10.0, 10.0, 10.0, 10.0, 0.0, 10.0, 10.0, 0.0})
                                   .view({2, 4})
                                   .repeat({4, 1});  // [8, 4]: I, U, labelled, predicted
  const std::vector<std::uint64_t> seeds = {7, 7, 3, 3, 9, 9, 5, 5};
  std::vector<int64_t> all(8);
  std::iota(all.begin(), all.end(), int64_t{0});
  IouInterval interval = sceneBootstrapIou(halves, seeds, all);
  EXPECT_EQ(interval.scenes, 4);
  EXPECT_DOUBLE_EQ(interval.low, 0.5);
  EXPECT_DOUBLE_EQ(interval.high, 0.5);

  // Scenes that differ: an interval around the pooled IoU, the same for the same seed.
  const torch::Tensor counts =
      torch::tensor({{2.0, 10.0}, {9.0, 10.0}, {5.0, 10.0}, {1.0, 10.0}, {7.0, 10.0}});
  const std::vector<std::uint64_t> five = {1, 2, 3, 4, 5};
  const std::vector<int64_t> frames = {0, 1, 2, 3, 4};
  interval = sceneBootstrapIou(counts, five, frames, 4000, 11);
  EXPECT_EQ(interval.scenes, 5);
  EXPECT_LT(interval.low, 0.48);
  EXPECT_GT(interval.high, 0.48);  // the pooled 24 / 50
  EXPECT_GE(interval.low, 0.1);    // no draw below the worst scene's or above the best's
  EXPECT_LE(interval.high, 0.9);
  const IouInterval again = sceneBootstrapIou(counts, five, frames, 4000, 11);
  EXPECT_EQ(again.low, interval.low);
  EXPECT_EQ(again.high, interval.high);
  // Only the frames asked for: one scene alone has no spread.
  interval = sceneBootstrapIou(counts, five, {1});
  EXPECT_EQ(interval.scenes, 1);
  EXPECT_DOUBLE_EQ(interval.low, 0.9);
  EXPECT_DOUBLE_EQ(interval.high, 0.9);
  EXPECT_THROW(sceneBootstrapIou(counts, {1, 2}, frames), InvalidArgumentError);
}

// The gap between two sets' IoUs is drawn scene by scene in both at once: a scene hard in one set
// and as hard in the other moves both IoUs alike and not the gap.
TEST(LearningTest, TheIouGapsIntervalPairsTheScenes) {
  // Five scenes of very different IoU (0.2-0.9); in b each loses one of its ten pixels hit, so
  // every draw of the same scenes in both has a gap of exactly 0.1. Drawn apart, the scenes'
  // spread would make the interval tens of points wide.
  const torch::Tensor a =
      torch::tensor({{2.0, 10.0}, {9.0, 10.0}, {5.0, 10.0}, {3.0, 10.0}, {7.0, 10.0}});
  const std::vector<std::uint64_t> seeds_a = {1, 2, 3, 4, 5};
  // b: the same scenes in another order, scene 5 missing, scene 6 only here.
  const torch::Tensor b =
      torch::tensor({{4.0, 10.0}, {2.0, 10.0}, {1.0, 10.0}, {8.0, 10.0}, {0.0, 10.0}});
  const std::vector<std::uint64_t> seeds_b = {3, 4, 1, 2, 6};
  IouGap gap = sceneBootstrapIouGap(a, seeds_a, b, seeds_b, 4000, 3);
  EXPECT_EQ(gap.scenes, 4);
  EXPECT_NEAR(gap.gap, 0.1, 1e-12);  // (19 - 15) / 40 over the four shared scenes
  EXPECT_NEAR(gap.low, 0.1, 1e-12);
  EXPECT_NEAR(gap.high, 0.1, 1e-12);

  // Gaps that differ by scene: an interval around the pooled gap, the same for the same seed.
  const torch::Tensor c =
      torch::tensor({{2.0, 10.0}, {3.0, 10.0}, {5.0, 10.0}, {3.0, 10.0}, {2.0, 10.0}});
  gap = sceneBootstrapIouGap(a, seeds_a, c, seeds_a, 4000, 3);
  EXPECT_EQ(gap.scenes, 5);
  EXPECT_NEAR(gap.gap, 0.22, 1e-12);  // (26 - 15) / 50
  EXPECT_LT(gap.low, 0.22);
  EXPECT_GT(gap.high, 0.22);
  EXPECT_GE(gap.low, 0.0);  // no draw beyond the scenes' own gaps, 0 to 0.6
  EXPECT_LE(gap.high, 0.6);
  const IouGap again = sceneBootstrapIouGap(a, seeds_a, c, seeds_a, 4000, 3);
  EXPECT_EQ(again.low, gap.low);
  EXPECT_EQ(again.high, gap.high);

  EXPECT_THROW(sceneBootstrapIouGap(a, seeds_a, b, {7, 8, 9, 10, 11}), InvalidArgumentError)
      << "no scene in both";
  EXPECT_THROW(sceneBootstrapIouGap(a, {1, 2}, b, seeds_b), InvalidArgumentError);
}

// The escape error by the oracle's steps: each labelled frame in its row and in "all", frames
// without a label in none, rows without frames left out.
TEST(LearningTest, EscapeErrorsAreGroupedByTheOraclesSteps) {
  const torch::Tensor errors = torch::tensor({10.0f, 50.0f, 100.0f, NAN, 30.0f, 170.0f});
  const torch::Tensor steps = torch::tensor({1, 1, 2, 3, 7, 12}, torch::kInt);
  const nlohmann::json rows = escapeErrorsByOracleSteps(errors, steps);
  std::map<std::string, nlohmann::json> by_steps;
  for (const nlohmann::json& row : rows) by_steps[row["oracle_steps"]] = row;
  ASSERT_EQ(by_steps.size(), 5u) << rows.dump();
  EXPECT_EQ(by_steps.count("3"), 0u) << "its one frame has no label";
  EXPECT_EQ(by_steps.at("1")["frames"], 2);
  EXPECT_DOUBLE_EQ(by_steps.at("1")["mean_deg"].get<double>(), 30.0);
  EXPECT_DOUBLE_EQ(by_steps.at("1")["share_over_45_deg"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(by_steps.at("1")["share_over_90_deg"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(by_steps.at("2")["share_over_90_deg"].get<double>(), 1.0);
  EXPECT_EQ(by_steps.at("6-8")["frames"], 1);
  EXPECT_EQ(by_steps.at("9 or more")["frames"], 1);
  EXPECT_EQ(by_steps.at("all")["frames"], 5);
  EXPECT_DOUBLE_EQ(by_steps.at("all")["mean_deg"].get<double>(), 72.0);
  EXPECT_DOUBLE_EQ(by_steps.at("all")["median_deg"].get<double>(), 50.0);
  EXPECT_FALSE(by_steps.at("all").contains("share_shortest")) << "not asked for";

  // With whether each move was shortest (NaN: not recorded), the share per row.
  const torch::Tensor shortest = torch::tensor({1.0f, 0.0f, NAN, NAN, 1.0f, 0.0f});
  std::map<std::string, nlohmann::json> with;
  for (const nlohmann::json& row : escapeErrorsByOracleSteps(errors, steps, shortest))
    with[row["oracle_steps"]] = row;
  EXPECT_DOUBLE_EQ(with.at("1")["share_shortest"].get<double>(), 0.5);
  EXPECT_FALSE(with.at("2").contains("share_shortest")) << "none recorded";
  EXPECT_EQ(with.at("all")["frames_with_shortest_moves"], 4);
  EXPECT_DOUBLE_EQ(with.at("all")["share_shortest"].get<double>(), 0.5);
}

// The escape-bins head's targets from every shortest first move: each weighted by its depth in
// its run of shortest moves, read at the bins' directions; the check of a move against them; and
// the mirror that a flipped frame's moves take, which agrees with the flipped label.
TEST(LearningTest, ShortestMoveTargetsWeighTheMiddlesOfTheirRuns) {
  torch::Tensor moves = torch::zeros({4, 8});
  moves[0].slice(0, 1, 4).fill_(1.0);  // directions 1-3: depths 1, 2, 1
  moves[1][7] = moves[1][0] = 1.0;     // a run across direction 0: 1, 1
  moves[1][4] = 1.0;                   // and a lone one
  moves[2].fill_(1.0);                 // the whole circle: evenly
  // moves[3]: none
  const torch::Tensor targets = shortestMoveTargets(moves, 8);
  const torch::Tensor expected =
      torch::tensor({{0.f, .25f, .5f, .25f, 0.f, 0.f, 0.f, 0.f},
                     {1.f / 3, 0.f, 0.f, 0.f, 1.f / 3, 0.f, 0.f, 1.f / 3},
                     {.125f, .125f, .125f, .125f, .125f, .125f, .125f, .125f},
                     {0.f, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f}});
  EXPECT_TRUE(torch::allclose(targets, expected, 1e-6, 1e-6)) << targets;
  // At 4 bins, directions 0, 2, 4, 6: row 0 keeps direction 2 alone.
  const torch::Tensor fewer = shortestMoveTargets(moves, 4);
  EXPECT_TRUE(torch::allclose(fewer[0], torch::tensor({0.f, 1.f, 0.f, 0.f}))) << fewer;
  EXPECT_THROW(shortestMoveTargets(moves, 3), InvalidArgumentError);

  // A move is shortest when the circle's direction nearest it is.
  const auto unit = [](double angle) {
    return torch::tensor(
        {{static_cast<float>(std::sin(angle)), static_cast<float>(std::cos(angle))}});
  };
  const double step = 2.0 * M_PI / 8;
  EXPECT_EQ(isShortestMove(unit(2.4 * step), moves.slice(0, 0, 1)).item<float>(), 1.0f);
  EXPECT_EQ(isShortestMove(unit(3.6 * step), moves.slice(0, 0, 1)).item<float>(), 0.0f);
  EXPECT_EQ(isShortestMove(unit(-0.9 * step), moves.slice(0, 1, 2)).item<float>(), 1.0f);

  // Flipping the frame maps the label (sin, cos) to (sin, -cos); its moves mirror alike.
  const torch::Tensor mirrored = mirroredShortestMoves(moves);
  for (int k = 0; k < 8; ++k) {
    const torch::Tensor label = unit(k * step);
    const torch::Tensor flipped = torch::stack({label.select(1, 0), -label.select(1, 1)}, 1);
    for (int row = 0; row < 4; ++row) {
      EXPECT_EQ(isShortestMove(flipped, mirrored.slice(0, row, row + 1)).item<float>(),
                moves[row][k].item<float>())
          << "row " << row << ", direction " << k;
    }
  }
}

// A run whose escape-bins head aims at every shortest move: the option is checked, recorded only
// when it is not the default, and the run trains and reports which share of its moves is shortest.
TEST(LearningTest, AnEscapeBinsHeadTrainsOnEveryShortestMove) {
  TrainingOptions options = tinyTraining(1);
  options.escape_bin_targets = "shortest_moves";
  EXPECT_THROW(options.validate(), InvalidArgumentError) << "no bins head";
  options.network.escape_bins = 12;
  EXPECT_THROW(options.validate(), InvalidArgumentError) << "12 does not divide 64";
  options.network.escape_bins = 16;
  EXPECT_NO_THROW(options.validate());
  EXPECT_EQ(options.toJson().value("escape_bin_targets", ""), "shortest_moves");
  TrainingOptions bump = options;
  bump.escape_bin_targets = "label";
  EXPECT_FALSE(bump.toJson().contains("escape_bin_targets")) << "earlier runs' identity";
  options.escape_bin_targets = "nearest";
  EXPECT_THROW(options.validate(), InvalidArgumentError);
  options.escape_bin_targets = "shortest_moves";

  const fs::path data_dir = temporaryDir("occlusion_env_learning_shortest_data");
  dataset::generateDataset(data_dir.string(), tinyDataset(4, 4, 0.25));
  const TrainingData data = loadTrainingData(data_dir.string(), 32);
  const torch::Tensor recorded = data.train.shortest_moves.sum(1) > 0;
  EXPECT_TRUE(torch::equal(recorded, data.train.escape_valid > 0.5))
      << "frames with a path record their shortest moves";
  const fs::path run_dir = temporaryDir("occlusion_env_learning_shortest_run");
  TrainingData unrecorded = data;  // as datasets labelled before the moves were recorded
  unrecorded.train.shortest_moves = torch::zeros_like(data.train.shortest_moves);
  EXPECT_THROW(train(unrecorded, options, run_dir.string(), {}), InvalidArgumentError);
  options.augment = true;  // flips mirror the moves
  const std::vector<EpochMetrics> epochs = train(data, options, run_dir.string(), {});
  ASSERT_EQ(epochs.size(), 1u);
  EXPECT_TRUE(std::isfinite(epochs[0].train_loss));
  for (const double share :
       {epochs[0].val_escape_shortest_share, epochs[0].val_escape_bins_shortest_share}) {
    EXPECT_GE(share, 0.0);
    EXPECT_LE(share, 1.0);
  }
  // The per-frame check agrees with the share.
  LoadedModel model = loadModel((run_dir / "best.pt").string());
  torch::Tensor errors, shortest;
  const EpochMetrics again = evaluate(model.network, data.validation, 4, "mse", &errors, &shortest);
  const torch::Tensor known = shortest.masked_select(shortest.isnan().logical_not());
  ASSERT_GT(known.numel(), 0);
  EXPECT_NEAR(known.mean().item<double>(), again.val_escape_bins_shortest_share, 1e-6);
  for (const fs::path& dir : {data_dir, run_dir}) fs::remove_all(dir);
}

// A model whose input clears floors and walls trains on a dataset's frames: each is cleared with
// its own intrinsics (scene_camera.json's cam_K), so a room's floor and walls enter as the void.
TEST(LearningTest, AClearedInputTrainsOnADatasetsFramesWithTheirIntrinsics) {
  const fs::path data_dir = temporaryDir("occlusion_env_learning_cleared_rooms");
  dataset::DatasetOptions rooms = tinyDataset(2, 3, 0.5);
  rooms.world = "room";
  rooms.oracle_labels = false;
  dataset::generateDataset(data_dir.string(), rooms);
  const dataset::BopDataset bop(data_dir.string());
  const InputFormat cleared(32, DepthGaps::kFilled, true);
  const TrainingData data = loadTrainingData(data_dir.string(), cleared);
  ASSERT_EQ(data.train.size(), 3);
  InputScratch scratch;
  const torch::Tensor expected = torch::empty({4, 32, 32});
  // The void's normalised depth, as in AClearedInputSeesTheWallBehindABoxAsTheVoid.
  const float far = 2.0f;
  int64_t row = 0, void_pixels = 0;
  for (const dataset::Frame& frame : bop.frames()) {
    ASSERT_GT(frame.intrinsics.fx, 0.0) << "frame " << row << " has its cam_K";
    if (frame.validation) continue;
    writeNetworkInput(bop.readRgb(frame), bop.readDepthMeters(frame), frame.intrinsics, cleared,
                      scratch, expected.data_ptr<float>());
    const torch::Tensor held = data.train.inputs[row].to(torch::kFloat);
    EXPECT_LE((held - expected).abs().max().item<float>(), 2e-3f) << "frame " << row;
    void_pixels += (held[3] == far).sum().item<int64_t>();
    ++row;
  }
  // A room seen from 4 m fills the frame, mostly with floor and wall: a quarter at least cleared.
  EXPECT_GT(void_pixels, row * 32 * 32 / 4);
  // Without the scenes' cam_K a cleared input cannot be made, and says why.
  for (int scene = 0; scene < 2; ++scene)
    fs::remove(data_dir / "train" / dataset::idName(scene) / "scene_camera.json");
  EXPECT_THROW(loadTrainingData(data_dir.string(), cleared), InvalidArgumentError);
  EXPECT_EQ(loadTrainingData(data_dir.string(), InputFormat(32, DepthGaps::kFilled)).train.size(),
            3);
  fs::remove_all(data_dir);
}

// The samples are held as half floats and bytes: each is its frame's network input to half
// precision and its thresholded occlusion map, in the dataset's frame order.
TEST(LearningTest, SamplesHoldEachFramesInputCompactly) {
  const fs::path data_dir = temporaryDir("occlusion_env_learning_compact");
  dataset::generateDataset(data_dir.string(), tinyDataset(2, 4, 0.5));
  const TrainingData data = loadTrainingData(data_dir.string(), 32);
  ASSERT_EQ(data.train.inputs.scalar_type(), torch::kHalf);
  ASSERT_EQ(data.train.masks.scalar_type(), torch::kUInt8);
  const dataset::BopDataset bop(data_dir.string());
  InputScratch scratch;
  const torch::Tensor expected = torch::empty({4, 32, 32});
  int64_t row = 0;
  for (const dataset::Frame& frame : bop.frames()) {
    if (frame.validation) continue;
    writeNetworkInput(bop.readRgb(frame), bop.readDepthMeters(frame), 32, scratch,
                      expected.data_ptr<float>());
    const torch::Tensor held = data.train.inputs[row].to(torch::kFloat);
    EXPECT_LE((held - expected).abs().max().item<float>(), 2e-3f) << "frame " << row;
    // A pixel is occluded where at least half of its area is.
    cv::Mat area;
    cv::resize(bop.readOcclusionMask(frame), area, cv::Size(32, 32), 0, 0, cv::INTER_AREA);
    const cv::Mat occluded = (area >= 128) / 255;
    const torch::Tensor mask = torch::from_blob(occluded.data, {1, 32, 32}, torch::kUInt8);
    EXPECT_TRUE(torch::equal(data.train.masks[row], mask)) << "frame " << row;
    ++row;
  }
  EXPECT_EQ(row, data.train.size());
  EXPECT_GT(data.train.masks.sum().item<int64_t>(), 0) << "some occlusion in the tiny scenes";

  // With a view crop, input and labels are both the frame's centre.
  InputFormat cropped(32);
  cropped.view_crop = 0.5;
  const TrainingData centres = loadTrainingData(data_dir.string(), cropped);
  row = 0;
  for (const dataset::Frame& frame : bop.frames()) {
    if (frame.validation) continue;
    writeNetworkInput(bop.readRgb(frame), bop.readDepthMeters(frame), cropped, scratch,
                      expected.data_ptr<float>());
    const torch::Tensor held = centres.train.inputs[row].to(torch::kFloat);
    EXPECT_LE((held - expected).abs().max().item<float>(), 2e-3f) << "cropped frame " << row;
    const cv::Mat whole = bop.readOcclusionMask(frame);
    cv::Mat area;
    cv::resize(whole(viewCropRect(whole.size(), 0.5)), area, cv::Size(32, 32), 0, 0,
               cv::INTER_AREA);
    const cv::Mat occluded = (area >= 128) / 255;
    const torch::Tensor mask = torch::from_blob(occluded.data, {1, 32, 32}, torch::kUInt8);
    EXPECT_TRUE(torch::equal(centres.train.masks[row], mask)) << "cropped frame " << row;
    ++row;
  }

  // With a view_field_of_view narrower than the frames' camera, both are its middle, found from
  // each frame's intrinsics.
  InputFormat angle(32);
  angle.view_field_of_view = 40.0 * M_PI / 180.0;
  const TrainingData middles = loadTrainingData(data_dir.string(), angle);
  row = 0;
  for (const dataset::Frame& frame : bop.frames()) {
    if (frame.validation) continue;
    writeNetworkInput(bop.readRgb(frame), bop.readDepthMeters(frame), frame.intrinsics, angle,
                      scratch, expected.data_ptr<float>());
    const torch::Tensor held = middles.train.inputs[row].to(torch::kFloat);
    EXPECT_LE((held - expected).abs().max().item<float>(), 2e-3f) << "40 deg frame " << row;
    const cv::Mat whole = bop.readOcclusionMask(frame);
    const cv::Rect seen = seenViewRect(whole.size(), frame.intrinsics, angle);
    EXPECT_LT(seen.width, whole.cols * 0.7) << "40 deg of the frames' 60";
    cv::Mat area;
    cv::resize(whole(seen), area, cv::Size(32, 32), 0, 0, cv::INTER_AREA);
    const cv::Mat occluded = (area >= 128) / 255;
    const torch::Tensor mask = torch::from_blob(occluded.data, {1, 32, 32}, torch::kUInt8);
    EXPECT_TRUE(torch::equal(middles.train.masks[row], mask)) << "40 deg frame " << row;
    ++row;
  }
  fs::remove_all(data_dir);
}

TEST(LearningTest, NetworkInputFollowsTheConvention) {
  cv::Mat rgb(64, 64, CV_8UC3, cv::Scalar(255, 0, 128));
  cv::Mat depth(64, 64, CV_32FC1, cv::Scalar(4.0f));
  depth.at<float>(0, 0) = std::nanf("");
  InputScratch scratch;
  std::vector<float> out(4 * 32 * 32);
  writeNetworkInput(rgb, depth, 32, scratch, out.data());
  EXPECT_FLOAT_EQ(out[0], 2.0f);                // red 1.0 -> (1 - 0.5) / 0.25
  EXPECT_FLOAT_EQ(out[32 * 32], -2.0f);         // green 0
  EXPECT_FLOAT_EQ(out[3 * 32 * 32 + 5], 0.0f);  // 4 m of 8 m -> 0.5 -> 0
  EXPECT_GT(out[3 * 32 * 32], 0.0f);            // the NaN (far) pixel pulls its area up
  EXPECT_THROW(writeNetworkInput(rgb, cv::Mat(64, 64, CV_8UC1), 32, scratch, out.data()),
               InvalidArgumentError);
}

// DepthGaps::kFilled: a depth sensor's dropouts inside a surface take the surface's depth; the
// void around an object and a hole larger than a network pixel's neighbourhood stay far.
TEST(LearningTest, FilledDepthGapsLookLikeTheSurfaceAroundThem) {
  const cv::Mat rgb(64, 64, CV_8UC3, cv::Scalar(90, 90, 90));
  cv::Mat depth(64, 64, CV_32FC1, cv::Scalar(std::nanf("")));  // the void...
  depth(cv::Rect(16, 16, 32, 32)).setTo(2.0f);                 // ...and a box 2 m away
  cv::RNG random(7);
  for (int k = 0; k < 300; ++k) {  // speckle on the box, and one whole 2 x 2 network pixel
    depth.at<float>(16 + random.uniform(0, 32), 16 + random.uniform(0, 32)) = std::nanf("");
  }
  depth(cv::Rect(30, 30, 2, 2)).setTo(std::nanf(""));
  depth(cv::Rect(20, 40, 8, 6)).setTo(std::nanf(""));  // a hole of 4 x 3 network pixels
  InputScratch scratch;
  std::vector<float> filled(4 * 32 * 32), far(4 * 32 * 32);
  writeNetworkInput(rgb, depth, InputFormat(32, DepthGaps::kFilled), scratch, filled.data());
  writeNetworkInput(rgb, depth, InputFormat(32, DepthGaps::kFar), scratch, far.data());
  const auto at = [](const std::vector<float>& input, int row, int col) {
    return input[3 * 32 * 32 + row * 32 + col];
  };
  const float two_metres = (2.0f / 8.0f - 0.5f) / 0.25f, void_far = (1.0f - 0.5f) / 0.25f;
  int speckled = 0;
  for (int row = 8; row < 24; ++row) {
    for (int col = 8; col < 24; ++col) {
      if (row >= 20 && row < 23 && col >= 10 && col < 14) continue;  // the hole
      EXPECT_FLOAT_EQ(at(filled, row, col), two_metres) << row << ", " << col;
      if (at(far, row, col) > two_metres + 1e-3f) ++speckled;
    }
  }
  EXPECT_GT(speckled, 50) << "with far gaps, the speckle shows";
  EXPECT_FLOAT_EQ(at(filled, 21, 12), void_far) << "a hole's middle stays far";
  EXPECT_FLOAT_EQ(at(filled, 2, 2), void_far) << "the void stays far";
  EXPECT_FLOAT_EQ(at(filled, 12, 7), void_far) << "beside the box's edge (3 of 8 neighbours on it)";
  for (int i = 0; i < 3 * 32 * 32; ++i) ASSERT_EQ(filled[i], far[i]) << "colour as before";
}

// depth_validity: channel: a fifth channel holds each network pixel's share of depth readings,
// so that a filled input still shows where a sensor lost them; the first four channels are
// those of the input without it, in every kind of gap and when floors and walls are cleared;
// the network takes five channels and trains on them, augmented and shifted.
TEST(LearningTest, AValidFractionChannelShowsWhereDepthWasRead) {
  const cv::Mat rgb(64, 64, CV_8UC3, cv::Scalar(90, 90, 90));
  cv::Mat depth(64, 64, CV_32FC1, cv::Scalar(std::nanf("")));  // the void...
  depth(cv::Rect(16, 16, 32, 32)).setTo(2.0f);                 // ...a box 2 m away...
  depth(cv::Rect(20, 20, 1, 2)).setTo(std::nanf(""));          // ...half a network pixel lost
  const std::size_t plane = 32 * 32;
  InputScratch scratch;
  for (const DepthGaps gaps : {DepthGaps::kFar, DepthGaps::kFilled}) {
    InputFormat with_channel(32, gaps);
    with_channel.valid_fraction_channel = true;
    ASSERT_EQ(with_channel.channels(), 5);
    std::vector<float> four(4 * plane), five(5 * plane);
    writeNetworkInput(rgb, depth, InputFormat(32, gaps), scratch, four.data());
    writeNetworkInput(rgb, depth, with_channel, scratch, five.data());
    for (std::size_t i = 0; i < 4 * plane; ++i) ASSERT_EQ(five[i], four[i]) << i;
    const auto valid = [&five, plane](int row, int col) {
      return five[4 * plane + row * 32 + col];
    };
    EXPECT_FLOAT_EQ(valid(2, 2), -2.0f) << "the void: nothing read";
    EXPECT_FLOAT_EQ(valid(12, 12), 2.0f) << "the box: all read";
    EXPECT_FLOAT_EQ(valid(10, 10), (0.5f - 0.5f) / 0.25f) << "half lost";
  }
  // Cleared: a wall behind the box enters as the void, with nothing read.
  cv::Mat room(128, 128, CV_32FC1, cv::Scalar(2.0f));
  room(cv::Rect(32, 32, 64, 64)).setTo(1.2f);
  const cv::Mat grey(128, 128, CV_8UC3, cv::Scalar(120, 120, 120));
  const CameraIntrinsics intrinsics = CameraIntrinsics::fromFieldOfView(128, 128, M_PI / 3.0);
  InputFormat cleared(32, DepthGaps::kFilled, true);
  cleared.valid_fraction_channel = true;
  std::vector<float> four(4 * plane), five(5 * plane);
  writeNetworkInput(grey, room, intrinsics, InputFormat(32, DepthGaps::kFilled, true), scratch,
                    four.data());
  writeNetworkInput(grey, room, intrinsics, cleared, scratch, five.data());
  for (std::size_t i = 0; i < 4 * plane; ++i) ASSERT_EQ(five[i], four[i]) << i;
  EXPECT_FLOAT_EQ(five[4 * plane + 2 * 32 + 2], -2.0f) << "the wall, cleared";
  EXPECT_FLOAT_EQ(five[4 * plane + 16 * 32 + 16], 2.0f) << "the box, read";

  NetworkConfig config;
  config.input_size = 32;
  EXPECT_FALSE(config.toJson().contains("depth_validity")) << "older models' identity kept";
  EXPECT_EQ(config.inputFormat().channels(), 4);
  config.depth_validity = "channel";
  EXPECT_EQ(NetworkConfig::fromJson(config.toJson()).inputFormat().channels(), 5);
  MultiTaskUNet network(config);
  network->eval();
  EXPECT_EQ(network->forward(torch::zeros({2, 5, 32, 32})).occlusion_logits.sizes(),
            torch::IntArrayRef({2, 1, 32, 32}));
  EXPECT_ANY_THROW(network->forward(torch::zeros({2, 4, 32, 32}))) << "five channels, not four";
  config.depth_validity = "mask";
  EXPECT_THROW(config.validate(), InvalidArgumentError);

  // Trained on a dataset's frames with augmentation and shifts: the samples hold five channels,
  // and a loaded model estimates through the same format.
  const fs::path data_dir = temporaryDir("occlusion_env_learning_valid_channel");
  dataset::generateDataset(data_dir.string(), tinyDataset(2, 4, 0.5));
  TrainingOptions options = tinyTraining(1);
  options.batch_size = 2;
  options.network.depth_gaps = "filled";
  options.network.depth_validity = "channel";
  options.augment = true;
  options.shift = 0.25;
  const TrainingData data = loadTrainingData(data_dir.string(), options.network.inputFormat());
  ASSERT_EQ(data.train.inputs.size(1), 5);
  const fs::path run_dir = temporaryDir("occlusion_env_learning_valid_channel_run");
  const auto history = train(data, options, run_dir.string(), {});
  ASSERT_EQ(history.size(), 1u);
  EXPECT_TRUE(std::isfinite(history.back().train_loss));
  LoadedModel model = loadModel((run_dir / "best.pt").string());
  EXPECT_EQ(model.network->config().depth_validity, "channel");
  for (const fs::path& dir : {data_dir, run_dir}) fs::remove_all(dir);
}

// depth_reference: radius: a scene scaled with its sphere (everything, the camera's radius too,
// times s) enters as the unscaled scene read in metres; the void stays far; the format needs the
// radius, and a manifest records the field only when it is not metres.
TEST(LearningTest, DepthRelativeToTheRadiusMakesAScaledSceneTheSameInput) {
  const cv::Mat rgb(64, 64, CV_8UC3, cv::Scalar(90, 120, 150));
  cv::Mat depth(64, 64, CV_32FC1, cv::Scalar(std::nanf("")));  // the void...
  depth(cv::Rect(8, 8, 40, 40)).setTo(3.5f);                   // ...a box at 3.5 m...
  depth(cv::Rect(20, 30, 30, 20)).setTo(4.25f);                // ...and one behind it
  depth.at<float>(10, 10) = std::nanf("");                     // a dropout
  const double scale = 0.3;                                    // the sphere of 1.2 m
  const cv::Mat scaled_depth = depth * scale;
  for (const DepthGaps gaps : {DepthGaps::kFar, DepthGaps::kFilled}) {
    InputScratch scratch;
    std::vector<float> metres(4 * 32 * 32), relative(4 * 32 * 32);
    writeNetworkInput(rgb, depth, InputFormat(32, gaps), scratch, metres.data());
    const InputFormat per_radius(32, gaps, false, true);
    writeNetworkInput(rgb, scaled_depth, per_radius.atRadius(kWorkingRadiusM * scale), scratch,
                      relative.data());
    for (std::size_t i = 0; i < metres.size(); ++i) {
      ASSERT_NEAR(relative[i], metres[i], 1e-5f) << "element " << i;
    }
    EXPECT_FLOAT_EQ(relative[3 * 32 * 32], 2.0f) << "the void stays far";
    // At the working radius the input is the metres' one.
    writeNetworkInput(rgb, depth, per_radius.atRadius(kWorkingRadiusM), scratch, relative.data());
    EXPECT_EQ(relative, metres);
    EXPECT_THROW(writeNetworkInput(rgb, depth, per_radius, scratch, relative.data()),
                 InvalidArgumentError)
        << "no radius given";
  }
  NetworkConfig config;
  EXPECT_FALSE(config.toJson().contains("depth_reference"));
  EXPECT_FALSE(config.inputFormat().depth_per_radius);
  config.depth_reference = "radius";
  EXPECT_EQ(config.toJson().at("depth_reference"), "radius");
  EXPECT_TRUE(NetworkConfig::fromJson(config.toJson()).inputFormat().depth_per_radius);
  config.depth_reference = "feet";
  EXPECT_THROW(config.validate(), InvalidArgumentError);
}

// The same with a wall beyond the far limit and blocks that see both it and a box: each reading
// is clamped where the network's depth is far, so the box's edge reads as at 4 m whether the
// sphere is larger (the wall's readings were clamped at 8 m, too near) or smaller (they counted
// beyond far into the block's mean). Failed before the clamp followed the radius.
TEST(LearningTest, DepthBeyondFarRelativeToTheRadiusReadsAsAtFourMetres) {
  const cv::Mat rgb(64, 64, CV_8UC3, cv::Scalar(90, 120, 150));
  cv::Mat depth(64, 64, CV_32FC1, cv::Scalar(10.0f));  // a wall 10 m away...
  depth(cv::Rect(9, 9, 37, 37)).setTo(3.5f);           // ...a box whose edges split 2 x 2 blocks
  depth.at<float>(20, 20) = std::nanf("");             // a dropout
  for (const bool valid_channel : {false, true}) {
    InputFormat per_radius(32, DepthGaps::kFilled, false, true);
    per_radius.valid_fraction_channel = valid_channel;
    const std::size_t count = static_cast<std::size_t>(per_radius.channels()) * 32 * 32;
    InputScratch scratch;
    std::vector<float> at_four(count), scaled(count);
    writeNetworkInput(rgb, depth, per_radius.atRadius(kWorkingRadiusM), scratch, at_four.data());
    for (const double scale : {0.5, 2.0, 0.15}) {
      const cv::Mat scaled_depth = depth * scale;
      writeNetworkInput(rgb, scaled_depth, per_radius.atRadius(kWorkingRadiusM * scale), scratch,
                        scaled.data());
      for (std::size_t i = 0; i < count; ++i) {
        ASSERT_NEAR(scaled[i], at_four[i], 1e-5f)
            << "element " << i << " at " << scale << " x the radius";
      }
    }
  }
}

// view_crop: the network sees the view's centred part at its size, as a camera with the
// cropped intrinsics would see it alone; models without one record none.
TEST(LearningTest, AViewCropIsTheInputOfTheCentralPartAlone) {
  EXPECT_EQ(viewCropRect(cv::Size(256, 256), 0.5), cv::Rect(64, 64, 128, 128));
  EXPECT_EQ(viewCropRect(cv::Size(640, 480), 0.5), cv::Rect(160, 120, 320, 240));
  EXPECT_EQ(viewCropRect(cv::Size(100, 60), 1.0), cv::Rect(0, 0, 100, 60));
  EXPECT_THROW(viewCropRect(cv::Size(100, 60), 0.0), InvalidArgumentError);
  EXPECT_THROW(viewCropRect(cv::Size(100, 60), 1.5), InvalidArgumentError);

  // A floor, a wall and two boxes, one in front of the other, off the centre.
  cv::Mat rgb(128, 128, CV_8UC3, cv::Scalar(60, 70, 80));
  cv::Mat depth(128, 128, CV_32FC1, cv::Scalar(3.0f));
  depth.rowRange(80, 128).setTo(2.0f);
  depth(cv::Rect(40, 40, 30, 30)).setTo(1.5f);
  rgb(cv::Rect(40, 40, 30, 30)).setTo(cv::Scalar(200, 30, 30));
  depth(cv::Rect(55, 50, 30, 20)).setTo(1.2f);
  rgb(cv::Rect(55, 50, 30, 20)).setTo(cv::Scalar(30, 200, 30));
  depth.at<float>(60, 60) = std::nanf("");
  const CameraIntrinsics intrinsics = CameraIntrinsics::fromFieldOfView(128, 128, M_PI / 3.0);
  const cv::Rect crop = viewCropRect(rgb.size(), 0.5);
  const cv::Mat rgb_crop = rgb(crop).clone(), depth_crop = depth(crop).clone();
  for (const DepthGaps gaps : {DepthGaps::kFar, DepthGaps::kFilled}) {
    for (const bool clear_surfaces : {false, true}) {
      InputFormat whole(32, gaps, clear_surfaces);
      InputFormat cropped = whole;
      cropped.view_crop = 0.5;
      InputScratch scratch;
      std::vector<float> of_crop(4 * 32 * 32), alone(4 * 32 * 32), uncropped(4 * 32 * 32);
      writeNetworkInput(rgb, depth, intrinsics, cropped, scratch, of_crop.data());
      writeNetworkInput(rgb_crop, depth_crop, croppedIntrinsics(intrinsics, crop), whole, scratch,
                        alone.data());
      EXPECT_EQ(of_crop, alone) << "gaps " << static_cast<int>(gaps) << ", cleared "
                                << clear_surfaces;
      writeNetworkInput(rgb, depth, intrinsics, whole, scratch, uncropped.data());
      EXPECT_NE(of_crop, uncropped) << "the crop is not the whole view";
      if (!clear_surfaces) {
        writeNetworkInput(rgb, depth, cropped, scratch, of_crop.data());
        writeNetworkInput(rgb_crop, depth_crop, whole, scratch, alone.data());
        EXPECT_EQ(of_crop, alone) << "without intrinsics";
      }
    }
  }
  const CameraIntrinsics moved = croppedIntrinsics(intrinsics, crop);
  EXPECT_EQ(moved.width, 64);
  EXPECT_DOUBLE_EQ(moved.cx, intrinsics.cx - 32.0);
  EXPECT_DOUBLE_EQ(moved.fx, intrinsics.fx);

  NetworkConfig config;
  EXPECT_FALSE(config.toJson().contains("view_crop"));
  EXPECT_DOUBLE_EQ(config.inputFormat().view_crop, 1.0);
  config.view_crop = 0.5;
  EXPECT_DOUBLE_EQ(config.toJson().at("view_crop").get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(NetworkConfig::fromJson(config.toJson()).inputFormat().view_crop, 0.5);
  config.view_crop = 0.05;
  EXPECT_THROW(config.validate(), InvalidArgumentError);
}

// view_field_of_view: the network sees a fixed angle of view around the principal point,
// whatever the camera's own: through a 90 deg camera the middle 60 deg, as a 60 deg camera
// would see it; the paper's camera at 60 deg unchanged; beyond a narrower image the void.
TEST(LearningTest, AViewFieldOfViewIsTheSameAngleThroughEveryCamera) {
  const double sixty = M_PI / 3.0;
  InputFormat format(32, DepthGaps::kFilled);
  format.view_field_of_view = sixty;
  const CameraIntrinsics paper = CameraIntrinsics::fromFieldOfView(128, 128, sixty);
  EXPECT_EQ(seenViewRect(cv::Size(128, 128), paper, format), cv::Rect(0, 0, 128, 128));
  // 90 deg over 128 px: fx = 64, 60 deg span 2 * 64 tan(30 deg) = 73.9 px around the centre.
  const CameraIntrinsics wide = CameraIntrinsics::fromFieldOfView(128, 128, M_PI / 2.0);
  EXPECT_EQ(seenViewRect(cv::Size(128, 128), wide, format), cv::Rect(27, 27, 74, 74));
  // 45 deg over 128 px: the 60 deg square reaches 25 px beyond each edge.
  const CameraIntrinsics narrow = CameraIntrinsics::fromFieldOfView(128, 128, M_PI / 4.0);
  const cv::Rect beyond = seenViewRect(cv::Size(128, 128), narrow, format);
  EXPECT_EQ(beyond, cv::Rect(-25, -25, 178, 178));
  // The principal point moves the square with it.
  CameraIntrinsics shifted = wide;
  shifted.cx += 10.0;
  EXPECT_EQ(seenViewRect(cv::Size(128, 128), shifted, format), cv::Rect(37, 27, 74, 74));
  InputFormat no_crop(32);
  EXPECT_EQ(seenViewRect(cv::Size(100, 60), CameraIntrinsics{}, no_crop), cv::Rect(0, 0, 100, 60));
  EXPECT_THROW(seenViewRect(cv::Size(128, 128), CameraIntrinsics{}, format), InvalidArgumentError);

  // Two boxes, one in front of the other, and a dropout.
  cv::Mat rgb(128, 128, CV_8UC3, cv::Scalar(60, 70, 80));
  cv::Mat depth(128, 128, CV_32FC1, cv::Scalar(3.0f));
  depth(cv::Rect(40, 40, 30, 30)).setTo(1.5f);
  rgb(cv::Rect(40, 40, 30, 30)).setTo(cv::Scalar(200, 30, 30));
  depth(cv::Rect(55, 50, 30, 20)).setTo(1.2f);
  depth.at<float>(60, 60) = std::nanf("");
  InputFormat whole = format;
  whole.view_field_of_view = 0.0;
  InputScratch scratch;
  std::vector<float> seen(4 * 32 * 32), alone(4 * 32 * 32);
  // At the paper's camera: the input of the whole view, bit for bit.
  writeNetworkInput(rgb, depth, paper, format, scratch, seen.data());
  writeNetworkInput(rgb, depth, paper, whole, scratch, alone.data());
  EXPECT_EQ(seen, alone);
  // Through the wide camera: the input of its middle alone.
  const cv::Rect middle(27, 27, 74, 74);
  writeNetworkInput(rgb, depth, wide, format, scratch, seen.data());
  writeNetworkInput(rgb(middle).clone(), depth(middle).clone(), croppedIntrinsics(wide, middle),
                    whole, scratch, alone.data());
  EXPECT_EQ(seen, alone);
  // Through the narrow camera: the image padded with black and no depth (far) around it.
  writeNetworkInput(rgb, depth, narrow, format, scratch, seen.data());
  cv::Mat rgb_padded(178, 178, CV_8UC3, cv::Scalar::all(0));
  cv::Mat depth_padded(178, 178, CV_32FC1, cv::Scalar::all(std::nanf("")));
  rgb.copyTo(rgb_padded(cv::Rect(25, 25, 128, 128)));
  depth.copyTo(depth_padded(cv::Rect(25, 25, 128, 128)));
  writeNetworkInput(rgb_padded, depth_padded, croppedIntrinsics(narrow, beyond), whole, scratch,
                    alone.data());
  EXPECT_EQ(seen, alone);
  const float far = (1.0f - 0.5f) / 0.25f;
  EXPECT_FLOAT_EQ(seen[3 * 32 * 32 + 0], far) << "the corner beyond the image: far";
  EXPECT_THROW(writeNetworkInput(rgb, depth, format, scratch, seen.data()), InvalidArgumentError)
      << "it needs intrinsics";

  NetworkConfig config;
  EXPECT_FALSE(config.toJson().contains("view_field_of_view"));
  config.view_field_of_view = sixty;
  EXPECT_DOUBLE_EQ(NetworkConfig::fromJson(config.toJson()).inputFormat().view_field_of_view,
                   sixty);
  config.view_crop = 0.5;
  EXPECT_THROW(config.validate(), InvalidArgumentError) << "one crop at a time";
}

// bounding_surfaces: cleared: a wall behind a box enters as the void (black, far), the box as
// it is; a model that clears needs the camera's intrinsics, and its manifest says so.
TEST(LearningTest, AClearedInputSeesTheWallBehindABoxAsTheVoid) {
  const cv::Mat rgb(128, 128, CV_8UC3, cv::Scalar(120, 120, 120));
  cv::Mat depth(128, 128, CV_32FC1, cv::Scalar(2.0f));
  depth(cv::Rect(32, 32, 64, 64)).setTo(1.2f);  // network pixels 8..23 of 32
  const CameraIntrinsics intrinsics = CameraIntrinsics::fromFieldOfView(128, 128, M_PI / 3.0);
  InputScratch scratch;
  const std::size_t plane = 32 * 32;
  std::vector<float> kept(4 * plane), cleared(4 * plane);
  for (const DepthGaps gaps : {DepthGaps::kFar, DepthGaps::kFilled}) {
    writeNetworkInput(rgb, depth, intrinsics, InputFormat(32, gaps), scratch, kept.data());
    writeNetworkInput(rgb, depth, intrinsics, InputFormat(32, gaps, true), scratch, cleared.data());
    int on_wall = 0;
    for (int row = 0; row < 32; ++row) {
      for (int col = 0; col < 32; ++col) {
        const std::size_t i = static_cast<std::size_t>(row) * 32 + col;
        const bool box = row >= 8 && row < 24 && col >= 8 && col < 24;
        if (box) {
          for (int c = 0; c < 4; ++c) EXPECT_EQ(cleared[c * plane + i], kept[c * plane + i]);
          continue;
        }
        ++on_wall;
        for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(cleared[c * plane + i], -2.0f);  // black
        EXPECT_FLOAT_EQ(cleared[3 * plane + i], 2.0f);                               // far
        EXPECT_LT(kept[3 * plane + i], 0.0f);                                        // 2 m
      }
    }
    EXPECT_EQ(on_wall, 32 * 32 - 16 * 16);
  }
  EXPECT_THROW(writeNetworkInput(rgb, depth, InputFormat(32, DepthGaps::kFilled, true), scratch,
                                 cleared.data()),
               InvalidArgumentError);
  EXPECT_THROW(
      writeNetworkInput(rgb, depth, CameraIntrinsics{}, InputFormat(32, DepthGaps::kFilled, true),
                        scratch, cleared.data()),
      InvalidArgumentError);

  NetworkConfig config;
  EXPECT_FALSE(config.toJson().contains("bounding_surfaces")) << "older models' identity kept";
  EXPECT_FALSE(config.inputFormat().clear_bounding_surfaces);
  config.bounding_surfaces = "cleared";
  EXPECT_TRUE(NetworkConfig::fromJson(config.toJson()).inputFormat().clear_bounding_surfaces);
  config.bounding_surfaces = "removed";
  EXPECT_THROW(config.validate(), InvalidArgumentError);
}

TEST(LearningTest, AClearedInputShowsWhereNoDepthWasReadAsTheVoid) {
  const cv::Mat rgb(128, 128, CV_8UC3, cv::Scalar(120, 120, 120));
  cv::Mat depth(128, 128, CV_32FC1, cv::Scalar(2.0f));
  depth(cv::Rect(32, 32, 64, 64)).setTo(1.2f);  // a box before a wall, as above
  // Beyond the sensor's range: network pixels 0..3 x 0..3 read nothing; 28..31 x 0..3 read a
  // quarter of their blocks (too little for a plane point, but not nothing).
  depth(cv::Rect(0, 0, 16, 16)).setTo(std::numeric_limits<float>::quiet_NaN());
  for (int row = 0; row < 16; ++row) {
    for (int col = 112; col < 128; ++col) {
      if (row % 2 == 1 || col % 2 == 1) depth.at<float>(row, col) = NAN;
    }
  }
  const CameraIntrinsics intrinsics = CameraIntrinsics::fromFieldOfView(128, 128, M_PI / 3.0);
  InputScratch scratch;
  const std::size_t plane = 32 * 32;
  std::vector<float> kept(4 * plane), cleared(4 * plane);
  writeNetworkInput(rgb, depth, intrinsics, InputFormat(32, DepthGaps::kFilled), scratch,
                    kept.data());
  writeNetworkInput(rgb, depth, intrinsics, InputFormat(32, DepthGaps::kFilled, true), scratch,
                    cleared.data());
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) {
      const std::size_t i = static_cast<std::size_t>(row) * 32 + col;
      EXPECT_GT(kept[i], -2.0f) << "kept: the wall's colour stays";
      for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(cleared[c * plane + i], -2.0f);  // black
      EXPECT_FLOAT_EQ(cleared[3 * plane + i], 2.0f);                               // far
    }
  }
  // The box, and the network pixels that read a quarter of their blocks, are as the kept input
  // has them.
  for (int row = 0; row < 24; ++row) {
    for (int col = 8; col < 32; ++col) {
      const bool box = row >= 8 && col < 24, quarter = row < 4 && col >= 28;
      if (!box && !quarter) continue;
      const std::size_t i = static_cast<std::size_t>(row) * 32 + col;
      for (int c = 0; c < 4; ++c) EXPECT_EQ(cleared[c * plane + i], kept[c * plane + i]);
    }
  }
}

// A camera 1 m above a floor looking level (60 deg, size x size px); a box's front face 3 m
// ahead stands on the floor, 0.5 m tall. `box` is 255 on the face's pixels.
struct FloorAndBox {
  CameraIntrinsics intrinsics;
  cv::Mat depth, box;
};

FloorAndBox floorAndBox(int size) {
  FloorAndBox scene{
      CameraIntrinsics::fromFieldOfView(size, size, M_PI / 3.0),
      cv::Mat(size, size, CV_32FC1, cv::Scalar(std::numeric_limits<float>::quiet_NaN())),
      cv::Mat(size, size, CV_8UC1, cv::Scalar(0))};
  const CameraIntrinsics& intrinsics = scene.intrinsics;
  for (int v = 0; v < size; ++v) {
    const double y = (v - intrinsics.cy) / intrinsics.fy;  // ray's drop per metre ahead
    for (int u = 0; u < size; ++u) {
      const double x = (u - intrinsics.cx) / intrinsics.fx;
      const bool face = std::abs(x * 3.0) < 0.6 && y * 3.0 >= 0.5 && y * 3.0 < 1.0;
      if (face) {
        scene.depth.at<float>(v, u) = 3.0f;
        scene.box.at<std::uint8_t>(v, u) = 255;
      } else if (y > 0.0) {
        scene.depth.at<float>(v, u) = static_cast<float>(1.0 / y);  // the floor
      }
    }
  }
  return scene;
}

// The network pixels (of `grid` x `grid`) wholly on the box that `on_surface` takes for floor.
int boxCellsOnSurface(const cv::Mat& box, const cv::Mat& on_surface, int grid) {
  const int block = box.rows / grid;
  int cells = 0;
  for (int row = 0; row < grid; ++row) {
    for (int col = 0; col < grid; ++col) {
      const cv::Rect cell(col * block, row * block, block, block);
      cells += cv::countNonZero(box(cell)) == block * block &&
               on_surface.at<std::uint8_t>(row, col) != 0;
    }
  }
  return cells;
}

TEST(LearningTest, AClearedInputKeepsTheFeetOfAnObjectOnTheFloor) {
  // At 3 m the finder's default tolerance (2 cm + 4 mm/m^2 z^2 = 5.6 cm) takes the box's lowest
  // rows for floor; a cleared input's (2 cm + 1 mm/m^2 z^2 = 2.9 cm) leaves them.
  const int size = 256, grid = 64;
  const FloorAndBox scene = floorAndBox(size);
  const CameraIntrinsics& intrinsics = scene.intrinsics;
  const cv::Mat &depth = scene.depth, &box = scene.box;
  const cv::Mat rgb(size, size, CV_8UC3, cv::Scalar(120, 120, 120));
  std::vector<float> cleared(4 * grid * grid);
  InputScratch scratch;
  writeNetworkInput(rgb, depth, intrinsics, InputFormat(grid, DepthGaps::kFilled, true), scratch,
                    cleared.data());
  const cv::Mat cleared_input_surface = scratch.on_surface.clone();
  BoundingSurfaceFinder default_finder;
  findGridBoundingSurfaces(intrinsics, rgb.size(), default_finder, scratch);
  int box_cells = 0, floor_cells = 0;
  for (int row = 0; row < grid; ++row) {
    for (int col = 0; col < grid; ++col) {
      const int box_pixels = cv::countNonZero(box(cv::Rect(col * 4, row * 4, 4, 4)));
      box_cells += box_pixels == 16;
      if (box_pixels == 0 && row > grid / 2 + 1) {
        floor_cells += cleared_input_surface.at<std::uint8_t>(row, col) != 0;
      }
    }
  }
  const int cleared_box_cells = boxCellsOnSurface(box, cleared_input_surface, grid);
  const int default_box_cells = boxCellsOnSurface(box, scratch.on_surface, grid);
  ASSERT_GT(box_cells, 100);
  EXPECT_GT(floor_cells, 500) << "the floor is found";
  EXPECT_GT(default_box_cells, 0) << "the finder's default takes the box's feet for floor";
  EXPECT_EQ(cleared_box_cells, 0) << "the cleared input keeps them";
}

TEST(LearningTest, AClearedInputReadRelativeToTheRadiusSearchesTheSceneAsAtFourMetres) {
  // The scene above scaled to a sphere of 1 m (every depth a quarter) and read by a model with
  // depth_reference: radius enters as the same scene at 4 m, floors and walls included: the plane
  // search's tolerances are those of 4 m (2.9 cm at the box), not 2 cm of a scene a quarter the
  // size (8 cm of the box at 4 m), which would take its feet for floor.
  const int size = 256, grid = 64;
  FloorAndBox scene = floorAndBox(size);
  // The floor up to 7 m only: the input clamps depth at kFarDepthM (8 m) in metres before it
  // scales it, so the floor beyond would be far at 4 m and not at 1 m.
  scene.depth.setTo(std::numeric_limits<float>::quiet_NaN(), scene.depth > 7.0f);
  const cv::Mat quarter_depth = scene.depth * 0.25;
  const cv::Mat rgb(size, size, CV_8UC3, cv::Scalar(120, 120, 120));
  const InputFormat per_radius(grid, DepthGaps::kFilled, true, true);
  std::vector<float> at_four_metres(4 * grid * grid), at_one_metre(4 * grid * grid);
  InputScratch scratch;
  writeNetworkInput(rgb, scene.depth, scene.intrinsics, per_radius.atRadius(4.0), scratch,
                    at_four_metres.data());
  const cv::Mat surface_at_four_metres = scratch.on_surface.clone();
  writeNetworkInput(rgb, quarter_depth, scene.intrinsics, per_radius.atRadius(1.0), scratch,
                    at_one_metre.data());
  EXPECT_GT(cv::countNonZero(surface_at_four_metres), 500) << "the floor is found";
  EXPECT_EQ(cv::countNonZero(scratch.on_surface != surface_at_four_metres), 0);
  EXPECT_EQ(boxCellsOnSurface(scene.box, scratch.on_surface, grid), 0);
  int differing = 0;
  for (std::size_t i = 0; i < at_one_metre.size(); ++i) {
    differing += std::abs(at_one_metre[i] - at_four_metres[i]) > 1e-6f;
  }
  EXPECT_EQ(differing, 0) << "the same input";
  // Searched in metres, the quarter-size scene loses the box's feet.
  BoundingSurfaceFinder in_metres(clearedInputSurfaceOptions());
  findGridBoundingSurfaces(scene.intrinsics, rgb.size(), in_metres, scratch);
  EXPECT_GT(boxCellsOnSurface(scene.box, scratch.on_surface, grid), 0);
}

// A fresh 32 px network whose occlusion logits are all `logit` (the head's weights zeroed);
// `bounding_surfaces` as the manifest's field.
std::shared_ptr<LoadedModel> constantOcclusionModel(float logit, const NetworkConfig& config) {
  auto model = std::make_shared<LoadedModel>();
  model->network = MultiTaskUNet(config);
  model->network->eval();
  torch::NoGradGuard no_grad;
  for (auto& parameter : model->network->named_parameters()) {
    if (parameter.key() == "occlusion_head.weight") parameter.value().zero_();
    if (parameter.key() == "occlusion_head.bias") parameter.value().fill_(logit);
  }
  return model;
}

std::shared_ptr<LoadedModel> constantOcclusionModel(float logit,
                                                    const std::string& bounding_surfaces = "kept") {
  NetworkConfig config;
  config.input_size = 32;
  config.bounding_surfaces = bounding_surfaces;
  return constantOcclusionModel(logit, config);
}

// A fresh 32 px network whose gradient and escape heads both say (sin, cos), whatever they see.
std::shared_ptr<LoadedModel> constantDirectionModel(float sin, float cos) {
  NetworkConfig config;
  config.input_size = 32;
  auto model = std::make_shared<LoadedModel>();
  model->network = MultiTaskUNet(config);
  model->network->eval();
  torch::NoGradGuard no_grad;
  for (auto& parameter : model->network->named_parameters()) {
    for (const std::string head : {"gradient_head", "escape_head"}) {
      if (parameter.key() == head + ".2.weight") parameter.value().zero_();
      if (parameter.key() == head + ".2.bias") {
        parameter.value()[0] = sin;
        parameter.value()[1] = cos;
      }
    }
  }
  return model;
}

// A network reading depth relative to the camera's radius, in the estimator and the agent: a
// scene scaled with its sphere gives the estimate and the move of the unscaled one; the agent
// takes the radius from the rig's pose and refuses a view without one. The shipped void network,
// its manifest saying depth_reference: radius (as scripts/derive_model.py would write it).
TEST(LearningTest, ARadiusRelativeNetworkSeesAScaledSceneAsTheUnscaledOne) {
  const fs::path dir = temporaryDir("occlusion_env_learning_radius_model");
  fs::create_directories(dir);
  const fs::path source = defaultModelPath();
  fs::copy_file(source, dir / "radius.pt");
  nlohmann::json manifest = readManifest(source.string());
  manifest["network"]["depth_reference"] = "radius";
  std::ofstream(dir / "radius.json") << manifest.dump();
  const auto model = std::make_shared<LoadedModel>(loadModel((dir / "radius.pt").string()));
  ASSERT_TRUE(model->network->config().inputFormat().depth_per_radius);
  // An occluded start view at 4 m, and the same scene scaled to a sphere of 1.2 m.
  EnvironmentOptions options;
  options.width = options.height = 128;
  Environment environment(options);
  const StepResult start = environment.reset(2);
  const cv::Mat rgb = start.observation->rgb.clone(), depth = start.observation->depth.clone();
  const CameraIntrinsics intrinsics = start.info.intrinsics;
  const double radius_m = 1.2;
  const cv::Mat scaled_depth = depth * (radius_m / kWorkingRadiusM);

  OcclusionEstimator at_four_metres(model, 0.5), scaled(model, 0.5);
  scaled.setCameraRadius(radius_m);
  cv::Mat mask, scaled_mask;
  const OcclusionEstimate expected = at_four_metres.estimate(rgb, depth, intrinsics, mask);
  const OcclusionEstimate got = scaled.estimate(rgb, scaled_depth, intrinsics, scaled_mask);
  EXPECT_NEAR(got.mean_probability, expected.mean_probability, 1e-5);
  EXPECT_EQ(cv::countNonZero(mask != scaled_mask), 0);
  // The scaled depth read as if from 4 m is another input, with another answer.
  const OcclusionEstimate misread = at_four_metres.estimate(rgb, scaled_depth, intrinsics, mask);
  EXPECT_GT(std::abs(misread.mean_probability - expected.mean_probability), 1e-3);
  EXPECT_THROW(scaled.setCameraRadius(0.0), InvalidArgumentError);

  NetworkDirectionAgent agent(model, DirectionHead::kEscape);
  const auto act = [&](const cv::Mat& view_depth, double camera_radius_m) {
    agent.reset(1);
    RigObservation observation{rgb, view_depth};
    observation.intrinsics = intrinsics;
    observation.world_from_optical.translation() = Eigen::Vector3d(0.0, -camera_radius_m, 0.0);
    return agent.act(observation);
  };
  const Action far_move = act(depth, kWorkingRadiusM), near_move = act(scaled_depth, radius_m);
  EXPECT_NEAR(near_move.d_azimuth_rad, far_move.d_azimuth_rad, 1e-5);
  EXPECT_NEAR(near_move.d_elevation_rad, far_move.d_elevation_rad, 1e-5);
  const Action misread_move = act(scaled_depth, kWorkingRadiusM);
  EXPECT_GT(std::abs(misread_move.d_azimuth_rad - far_move.d_azimuth_rad) +
                std::abs(misread_move.d_elevation_rad - far_move.d_elevation_rad),
            1e-3);
  agent.reset(1);
  EXPECT_THROW(agent.act(RigObservation{rgb, depth}), InvalidArgumentError) << "no camera frame";
  fs::remove_all(dir);
}

// A compact copy of the default model (float16 or 8-bit weights) written to `copy`, loaded and
// run in float32: its file at most `size_ratio` of the model's, its estimate and its move those
// of the model to within the storage's rounding (the move's direction within `turn_deg`).
void expectCompactCopyActsAsTheModel(WeightStorage storage, const std::string& copy,
                                     double size_ratio, double turn_deg) {
  const std::string source = defaultModelPath();
  saveCompactCopy(source, copy, storage);
  EXPECT_LT(fs::file_size(copy), fs::file_size(source) * size_ratio);
  const auto full_model = std::make_shared<LoadedModel>(loadModel(source));
  const auto copied_model = std::make_shared<LoadedModel>(loadModel(copy));
  EXPECT_EQ(copied_model->manifest.at("copy_of"), source);
  for (const auto& item : copied_model->network->named_parameters()) {
    ASSERT_EQ(item.value().scalar_type(), torch::kFloat32) << item.key();
  }

  EnvironmentOptions options;
  options.width = options.height = 128;
  Environment environment(options);
  const StepResult start = environment.reset(2);
  const Observation& view = *start.observation;
  OcclusionEstimator full_estimator(full_model, 0.5), copied_estimator(copied_model, 0.5);
  cv::Mat full_mask, copied_mask;
  const OcclusionEstimate full =
      full_estimator.estimate(view.rgb, view.depth, start.info.intrinsics, full_mask);
  const OcclusionEstimate copied =
      copied_estimator.estimate(view.rgb, view.depth, start.info.intrinsics, copied_mask);
  ASSERT_GT(full.occluded_pixels, 0) << "an occluded view";
  EXPECT_NEAR(copied.mean_probability, full.mean_probability, 2e-3);
  EXPECT_LE(cv::countNonZero(full_mask != copied_mask), full.occluded_pixels / 50);
  NetworkDirectionAgent full_agent(full_model, DirectionHead::kEscape),
      copied_agent(copied_model, DirectionHead::kEscape);
  full_agent.reset(1);
  copied_agent.reset(1);
  const Action full_move = full_agent.act(rigObservationOf(start));
  const Action copied_move = copied_agent.act(rigObservationOf(start));
  const double turn_rad =
      std::abs(std::remainder(std::atan2(copied_move.d_elevation_rad, copied_move.d_azimuth_rad) -
                                  std::atan2(full_move.d_elevation_rad, full_move.d_azimuth_rad),
                              2.0 * M_PI));
  EXPECT_LT(turn_rad, turn_deg * M_PI / 180.0);
}

// Float16 weights: half the file; the move turns by about a degree here. Another stored type is
// refused, and so is a copy onto its source.
TEST(LearningTest, AHalfPrecisionCopyIsHalfTheFileAndEstimatesAsTheModel) {
  const fs::path dir = temporaryDir("occlusion_env_learning_half_model");
  fs::create_directories(dir);
  const std::string half = (dir / "half.pt").string();
  expectCompactCopyActsAsTheModel(WeightStorage::kFloat16, half, 0.55, 2.0);
  EXPECT_EQ(readManifest(half).at("weights"), "float16");

  // The shipped robust network is such a copy, and loads as one.
  const LoadedModel shipped = loadModel(
      (fs::path(defaultModelPath()).parent_path() / "multitask_unet64_robust.pt").string());
  EXPECT_EQ(shipped.manifest.at("weights"), "float16");
  EXPECT_EQ(shipped.network->config().base_channels, 16);

  nlohmann::json manifest = readManifest(half);
  manifest["weights"] = "bfloat16";
  std::ofstream((dir / "half.json").string()) << manifest.dump();
  EXPECT_THROW(loadModel(half), InvalidArgumentError);
  EXPECT_THROW(saveCompactCopy(half, half, WeightStorage::kFloat16), InvalidArgumentError);
  EXPECT_THROW(
      saveCompactCopy(defaultModelPath(), (dir / "f32.pt").string(), WeightStorage::kFloat32),
      InvalidArgumentError);
  fs::remove_all(dir);
}

// 8-bit weights (per output channel): a little over a quarter of the file, every weight within
// half a code's step of the model's, the move within a few degrees. A copy whose tensors do not
// fit the manifest's network is refused as a float32 file is.
TEST(LearningTest, AnEightBitCopyIsAQuarterOfTheFileAndEstimatesAsTheModel) {
  const fs::path dir = temporaryDir("occlusion_env_learning_eight_bit_model");
  fs::create_directories(dir);
  const std::string copy = (dir / "eight_bit.pt").string();
  expectCompactCopyActsAsTheModel(WeightStorage::kUint8, copy, 0.3, 4.0);
  EXPECT_EQ(readManifest(copy).at("weights"), "uint8");

  const LoadedModel source = loadModel(defaultModelPath()), copied = loadModel(copy);
  const auto copied_parameters = copied.network->named_parameters();
  for (const auto& item : source.network->named_parameters()) {
    const torch::Tensor& weights = item.value();
    const torch::Tensor difference = (copied_parameters[item.key()] - weights).abs();
    if (weights.dim() < 2) {
      EXPECT_EQ(difference.max().item<float>(), 0.0f) << item.key() << " is stored as it is";
      continue;
    }
    // Half of each output channel's step, (highest - lowest) / 255, and float rounding.
    const torch::Tensor rows = weights.reshape({weights.size(0), -1});
    const torch::Tensor half_step =
        (std::get<0>(rows.max(1)) - std::get<0>(rows.min(1))) / 510.0 + 1e-6;
    EXPECT_TRUE(
        (difference.reshape({weights.size(0), -1}) <= half_step.unsqueeze(1)).all().item<bool>())
        << item.key();
  }

  nlohmann::json manifest = readManifest(copy);
  manifest["network"]["base_channels"] = copied.network->config().base_channels * 2;
  std::ofstream((dir / "eight_bit.json").string()) << manifest.dump();
  EXPECT_THROW(loadModel(copy), InvalidArgumentError);
  fs::remove_all(dir);
}

// Each tensor keeps the type its network was built with, whatever type a file holds it in:
// BatchNorm's counters stay int64 through a float16 copy and through training from a network
// loaded from one. (libtorch's Module::load kept the module's type over the stored memory: a
// fine-tune from a fine-tune of a float16 file held int64 counters over 4 bytes, and copying it
// crashed.) A tensor whose stored bytes are fewer than its shape needs is refused by name.
TEST(LearningTest, ATensorKeepsItsTypeThroughCopiesAndFineTunes) {
  const fs::path dir = temporaryDir("occlusion_env_learning_tensor_types");
  fs::create_directories(dir);
  NetworkConfig config;
  config.input_size = 32;
  MultiTaskUNet trained(config);
  const auto expectBuiltTypes = [&](torch::nn::Module& module, const std::string& from) {
    MultiTaskUNet built(config);
    const auto built_tensors = built->named_buffers();
    int counters = 0;
    for (const auto& item : module.named_buffers()) {
      EXPECT_EQ(item.value().scalar_type(), built_tensors[item.key()].scalar_type())
          << item.key() << " from " << from;
      if (item.value().scalar_type() == torch::kInt64) ++counters;
    }
    EXPECT_GT(counters, 0) << "BatchNorm counts its batches";
    for (const auto& item : module.named_parameters()) {
      EXPECT_EQ(item.value().scalar_type(), torch::kFloat32) << item.key() << " from " << from;
    }
  };
  const std::string original = (dir / "original.pt").string();
  saveModel(trained, original, nlohmann::json::object());
  const std::string half = (dir / "half.pt").string();
  saveCompactCopy(original, half, WeightStorage::kFloat16);
  LoadedModel from_half = loadModel(half);
  expectBuiltTypes(*from_half.network, half);

  // The chain of a fine-tune from the float16 file, and one from that fine-tune.
  MultiTaskUNet fine_tuned(config);
  loadCheckedParameters(*fine_tuned, half, "the network", WeightStorage::kFloat16);
  const std::string first = (dir / "first.pt").string();
  saveModel(fine_tuned, first, nlohmann::json::object());
  MultiTaskUNet again(config);
  loadCheckedParameters(*again, first, "the network");
  expectBuiltTypes(*again, first);
  for (const auto& item : again->named_buffers()) {
    const torch::Tensor& tensor = item.value();
    EXPECT_GE(static_cast<int64_t>(tensor.storage().nbytes()),
              tensor.numel() * static_cast<int64_t>(tensor.element_size()))
        << item.key();
  }
  const std::string second = (dir / "second.pt").string();
  saveModel(again, second, nlohmann::json::object());
  const std::string second_half = (dir / "second_half.pt").string();
  saveCompactCopy(second, second_half, WeightStorage::kFloat16);
  expectBuiltTypes(*loadModel(second_half).network, second_half);

  // A file whose int64 counter views 4 bytes (as Module::load left one): refused by name.
  {
    torch::NoGradGuard no_grad;
    MultiTaskUNet broken(config);
    for (auto& item : broken->named_buffers()) {
      if (item.value().scalar_type() != torch::kInt64) continue;
      item.value().set_(torch::zeros({}, torch::kFloat32));
      break;
    }
    const std::string broken_path = (dir / "broken.pt").string();
    saveModel(broken, broken_path, nlohmann::json::object());
    MultiTaskUNet target(config);
    try {
      loadCheckedParameters(*target, broken_path, "the network");
      ADD_FAILURE() << "a tensor shorter than its shape was read";
    } catch (const InvalidArgumentError& error) {
      EXPECT_NE(std::string(error.what()).find("num_batches_tracked"), std::string::npos)
          << error.what();
    }
  }
  fs::remove_all(dir);
}

TEST(LearningTest, TheEscapeAgentTurnsAlongAFloorThatStopsItAndThePapersAgentDoesNot) {
  const auto model = constantDirectionModel(-0.95f, 0.3f);  // down, a little to +azimuth
  const cv::Mat rgb(64, 64, CV_8UC3, cv::Scalar(90, 90, 90));
  const cv::Mat depth(64, 64, CV_32FC1, cv::Scalar(3.0f));
  const double floor_rad = -0.08, step_rad = 0.05;
  for (const DirectionHead head : {DirectionHead::kEscape, DirectionHead::kGradient}) {
    NetworkDirectionAgent agent(model, head);
    agent.reset(1);
    SphericalPose pose{0.0, floor_rad + 0.02};
    Action last;
    for (int t = 0; t < 6; ++t) {
      RigObservation observation{rgb, depth};
      observation.intrinsics = CameraIntrinsics::fromFieldOfView(64, 64, M_PI / 3.0);
      observation.pose = pose;
      observation.last_action = last;
      observation.step_index = t;
      const Action action = agent.act(observation);
      const bool along_the_floor = action.d_elevation_rad == 0.0 && action.d_azimuth_rad > 0.0;
      if (head == DirectionHead::kEscape && t >= 1) {
        EXPECT_TRUE(along_the_floor) << "step " << t << ": " << action.d_elevation_rad;
      } else {
        EXPECT_LT(action.d_elevation_rad, 0.0) << "step " << t;  // as the network says
      }
      // The rig: a step of step_rad along the action, its elevation stopped at the floor.
      const double length = std::hypot(action.d_azimuth_rad, action.d_elevation_rad);
      pose.azimuth_rad += step_rad * action.d_azimuth_rad / length;
      pose.elevation_rad =
          std::max(floor_rad, pose.elevation_rad + step_rad * action.d_elevation_rad / length);
      last = action;
    }
  }
}

TEST(LearningTest, ShiftedFramesMoveWithTheirMasks) {
  torch::manual_seed(3);
  const int64_t n = 64, size = 16;
  torch::Tensor inputs = torch::zeros({n, 4, size, size});
  torch::Tensor masks = torch::zeros({n, 1, size, size});
  inputs.index_put_({torch::indexing::Slice(), torch::indexing::Slice(), 8, 8}, 1.0);
  masks.index_put_({torch::indexing::Slice(), 0, 8, 8}, 1.0);
  shiftFrames(inputs, masks, 0.25);  // up to 4 px
  int moved = 0;
  for (int64_t i = 0; i < n; ++i) {
    // The marked pixel is in the same place in all four channels and in the mask.
    const torch::Tensor at = masks[i][0].nonzero();
    ASSERT_EQ(at.size(0), 1);
    const int64_t y = at[0][0].item<int64_t>(), x = at[0][1].item<int64_t>();
    EXPECT_LE(std::abs(y - 8), 4);
    EXPECT_LE(std::abs(x - 8), 4);
    for (int c = 0; c < 4; ++c) EXPECT_EQ(inputs[i][c][y][x].item<float>(), 1.0f);
    moved += (x != 8 || y != 8);
    // The uncovered border is the void: black and far.
    if (x > 8) {
      EXPECT_EQ(inputs[i][0][0][0].item<float>(), -2.0f);
      EXPECT_EQ(inputs[i][3][0][0].item<float>(), 2.0f);
    }
  }
  EXPECT_GT(moved, n / 2);
  // No shift leaves frames as they are.
  const torch::Tensor before = inputs.clone();
  shiftFrames(inputs, masks, 0.0);
  EXPECT_TRUE(torch::equal(before, inputs));

  // A fifth channel (the valid fraction) moves with the rest; its uncovered border read nothing.
  torch::Tensor five = torch::zeros({n, 5, size, size});
  torch::Tensor five_masks = torch::zeros({n, 1, size, size});
  five.index_put_({torch::indexing::Slice(), torch::indexing::Slice(), 8, 8}, 1.0);
  five_masks.index_put_({torch::indexing::Slice(), 0, 8, 8}, 1.0);
  shiftFrames(five, five_masks, 0.25);
  for (int64_t i = 0; i < n; ++i) {
    const torch::Tensor at = five_masks[i][0].nonzero();
    ASSERT_EQ(at.size(0), 1);
    const int64_t y = at[0][0].item<int64_t>(), x = at[0][1].item<int64_t>();
    EXPECT_EQ(five[i][4][y][x].item<float>(), 1.0f);
    if (x > 8) EXPECT_EQ(five[i][4][0][0].item<float>(), -2.0f);
  }
}

TEST(LearningTest, DroppedDepthReadsAsFarAndNothingReadWithTheColourKept) {
  torch::manual_seed(4);
  const int64_t n = 200, size = 8;
  const torch::Tensor original = torch::rand({n, 5, size, size});
  torch::Tensor inputs = original.clone();
  dropDepth(inputs, 0.3);
  int dropped = 0;
  for (int64_t i = 0; i < n; ++i) {
    EXPECT_TRUE(torch::equal(inputs[i].slice(0, 0, 3), original[i].slice(0, 0, 3)));
    if (torch::equal(inputs[i][3], original[i][3])) {
      EXPECT_TRUE(torch::equal(inputs[i][4], original[i][4]));  // kept whole
      continue;
    }
    ++dropped;
    EXPECT_TRUE(inputs[i][3].eq(2.0).all().item<bool>());   // far, the void's depth
    EXPECT_TRUE(inputs[i][4].eq(-2.0).all().item<bool>());  // nothing read
  }
  EXPECT_GT(dropped, 40);  // 60 expected of 200
  EXPECT_LT(dropped, 80);
  // None asked: nothing changes and nothing is drawn; a four-channel input loses its depth too.
  torch::Tensor again = original.clone();
  dropDepth(again, 0.0);
  EXPECT_TRUE(torch::equal(again, original));
  torch::Tensor four = original.slice(1, 0, 4).clone();
  dropDepth(four, 1.0);
  EXPECT_TRUE(four.slice(1, 3, 4).eq(2.0).all().item<bool>());
  EXPECT_TRUE(torch::equal(four.slice(1, 0, 3), original.slice(1, 0, 3)));

  TrainingOptions options;
  EXPECT_FALSE(options.toJson().contains("depth_dropout")) << "runs without it keep their identity";
  options.depth_dropout = 0.25;
  EXPECT_DOUBLE_EQ(options.toJson().at("depth_dropout").get<double>(), 0.25);
  options.depth_dropout = 1.5;
  EXPECT_THROW(options.validate(), InvalidArgumentError);
}

TEST(LearningTest, OcclusionEstimatedOnAWallIsClearedAndOnAnObjectInFrontOfItKept) {
  // A network that says "occluded" everywhere, a wall 2 m away and a box 1.2 m away over the
  // middle quarter of the view (16 x 16 of the 32 x 32 network pixels).
  const cv::Mat rgb(128, 128, CV_8UC3, cv::Scalar(120, 120, 120));
  cv::Mat depth(128, 128, CV_32FC1, cv::Scalar(2.0f));
  const cv::Rect box(32, 32, 64, 64);
  depth(box).setTo(1.2f);
  const CameraIntrinsics intrinsics = CameraIntrinsics::fromFieldOfView(128, 128, M_PI / 3.0);
  cv::Mat mask;
  OcclusionEstimator plain(constantOcclusionModel(1.0f), 0.5);
  const OcclusionEstimate everywhere = plain.estimate(rgb, depth, intrinsics, mask);
  EXPECT_EQ(everywhere.occluded_pixels, 128 * 128);
  EXPECT_EQ(everywhere.cleared_pixels, 0);

  OcclusionEstimator clearing(constantOcclusionModel(1.0f), 0.5, BoundingSurfaceOptions{});
  const OcclusionEstimate on_the_box = clearing.estimate(rgb, depth, intrinsics, mask);
  EXPECT_EQ(on_the_box.occluded_pixels, box.area());
  EXPECT_EQ(on_the_box.cleared_pixels, 128 * 128 - box.area());
  EXPECT_EQ(cv::countNonZero(mask(box)), box.area());
  EXPECT_EQ(cv::countNonZero(mask), box.area());
  // A model that clears its input finds the same surfaces there, and the estimate reuses them.
  OcclusionEstimator cleared_input(constantOcclusionModel(1.0f, "cleared"), 0.5,
                                   BoundingSurfaceOptions{});
  const OcclusionEstimate reused = cleared_input.estimate(rgb, depth, intrinsics, mask);
  EXPECT_EQ(reused.occluded_pixels, box.area());
  EXPECT_EQ(reused.cleared_pixels, 128 * 128 - box.area());
  // The wall alone: nothing left.
  depth(box).setTo(2.0f);
  EXPECT_EQ(clearing.estimate(rgb, depth, intrinsics, mask).occluded_pixels, 0);
  EXPECT_EQ(cleared_input.estimate(rgb, depth, intrinsics, mask).occluded_pixels, 0);
}

// Several thresholds from one pass: each count is what an estimator at that threshold counts,
// its floors and walls cleared alike.
TEST(LearningTest, OccludedPixelsAtAnotherProbabilityAreThatEstimatorsCount) {
  NetworkConfig config;
  config.input_size = 32;
  auto model = std::make_shared<LoadedModel>();
  torch::manual_seed(3);
  model->network = MultiTaskUNet(config);
  model->network->eval();
  // A wall 2 m away and a box 1.2 m away in front of it (as above).
  cv::Mat rgb(96, 128, CV_8UC3, cv::Scalar(120, 110, 100));
  cv::Mat depth(96, 128, CV_32FC1, cv::Scalar(2.0f));
  depth(cv::Rect(40, 24, 48, 48)).setTo(1.2f);
  rgb(cv::Rect(40, 24, 48, 48)).setTo(cv::Scalar(200, 40, 40));
  const CameraIntrinsics intrinsics = CameraIntrinsics::fromFieldOfView(128, 96, M_PI / 3.0);
  cv::Mat mask;
  for (const bool clearing : {false, true}) {
    std::optional<BoundingSurfaceOptions> surfaces;
    if (clearing) surfaces.emplace();
    OcclusionEstimator one_pass(model, 0.5, surfaces);
    EXPECT_THROW(one_pass.occludedPixelsAt(0.5), InvalidStateError);
    one_pass.estimate(rgb, depth, intrinsics, mask);
    std::set<std::int64_t> counts;
    for (const double probability :
         {0.01, 0.3, 0.45, 0.48, 0.49, 0.5, 0.51, 0.52, 0.55, 0.7, 0.99}) {
      OcclusionEstimator alone(model, probability, surfaces);
      const std::int64_t expected = alone.estimate(rgb, depth, intrinsics, mask).occluded_pixels;
      EXPECT_EQ(one_pass.occludedPixelsAt(probability), expected)
          << "probability " << probability << (clearing ? ", cleared" : "");
      counts.insert(expected);
    }
    // Thresholds on both sides of the map: a count that ignored its probability would fail.
    EXPECT_GE(counts.size(), 2u) << "every threshold counts alike";
    EXPECT_THROW(one_pass.occludedPixelsAt(1.0), InvalidArgumentError);

    // Joined by a second estimate's map (the bridge's second opinion): each pixel once.
    cv::Mat second(rgb.size(), CV_8UC1, cv::Scalar(0));
    second(cv::Rect(0, 0, 64, 96)).setTo(255);  // the left half
    for (const double probability : {0.01, 0.5, 0.99}) {
      OcclusionEstimator alone(model, probability, surfaces);
      alone.estimate(rgb, depth, intrinsics, mask);
      EXPECT_EQ(one_pass.occludedPixelsAt(probability, second), cv::countNonZero(mask | second))
          << "probability " << probability << (clearing ? ", cleared" : "");
    }
    EXPECT_EQ(one_pass.occludedPixelsAt(0.5, cv::Mat::zeros(rgb.size(), CV_8UC1)),
              one_pass.occludedPixelsAt(0.5));
    EXPECT_THROW(one_pass.occludedPixelsAt(0.5, cv::Mat::zeros(10, 10, CV_8UC1)),
                 InvalidArgumentError);
  }
}

TEST(LearningTest, OcclusionEstimateIsTheThresholdedMapAtTheImagesSize) {
  // Not square, not 32 px, and views into larger images (as the bridge's central square is).
  const cv::Mat rgb_full(60, 100, CV_8UC3, cv::Scalar(90, 120, 30));
  const cv::Mat depth_full(60, 100, CV_32FC1, cv::Scalar(3.0f));
  const cv::Mat rgb = rgb_full(cv::Rect(10, 6, 80, 48));
  const cv::Mat depth = depth_full(cv::Rect(10, 6, 80, 48));
  const CameraIntrinsics intrinsics = CameraIntrinsics::fromFieldOfView(80, 48, 1.0);
  cv::Mat mask;
  // Logit 1: probability 0.73, occluded at the threshold 0.5, not at 0.9.
  OcclusionEstimator at_half(constantOcclusionModel(1.0f), 0.5);
  const OcclusionEstimate all = at_half.estimate(rgb, depth, intrinsics, mask);
  EXPECT_EQ(mask.size(), rgb.size());
  EXPECT_EQ(mask.type(), CV_8UC1);
  EXPECT_EQ(all.occluded_pixels, 48 * 80);
  EXPECT_EQ(cv::countNonZero(mask == 255), 48 * 80);
  EXPECT_NEAR(all.mean_probability, 1.0 / (1.0 + std::exp(-1.0)), 1e-5);
  OcclusionEstimator at_ninety(constantOcclusionModel(1.0f), 0.9);
  EXPECT_EQ(at_ninety.estimate(rgb, depth, intrinsics, mask).occluded_pixels, 0);
  EXPECT_EQ(cv::countNonZero(mask), 0);

  // A real network's map: the count is the mask's, whatever it predicts.
  NetworkConfig config;
  config.input_size = 32;
  auto model = std::make_shared<LoadedModel>();
  model->network = MultiTaskUNet(config);
  model->network->eval();
  OcclusionEstimator estimator(model);
  const OcclusionEstimate some = estimator.estimate(rgb, depth, intrinsics, mask);
  EXPECT_EQ(some.occluded_pixels, cv::countNonZero(mask));

  // A model with a view crop estimates the centre of the image only, at the image's size.
  config.view_crop = 0.5;
  OcclusionEstimator centre(constantOcclusionModel(1.0f, config), 0.5);
  EXPECT_EQ(centre.estimate(rgb, depth, intrinsics, mask).occluded_pixels, 24 * 40);
  EXPECT_EQ(mask.size(), rgb.size());
  EXPECT_EQ(cv::countNonZero(mask(cv::Rect(20, 12, 40, 24))), 24 * 40) << "the crop, all of it";
  EXPECT_EQ(centre.occludedPixelsAt(0.6), 24 * 40);
  EXPECT_EQ(centre.occludedPixelsAt(0.9), 0);

  // A model with a view_field_of_view wider than the camera's estimates inside the image only.
  config.view_crop = 1.0;
  config.view_field_of_view = 2.0 * std::atan(2.0 * std::tan(0.5));  // the camera: 1 rad
  OcclusionEstimator wider(constantOcclusionModel(1.0f, config), 0.5);
  EXPECT_EQ(wider.estimate(rgb, depth, intrinsics, mask).occluded_pixels, rgb.rows * rgb.cols)
      << "twice the camera's tangent: the image is the middle half of what it sees";
  EXPECT_EQ(mask.size(), rgb.size());
  EXPECT_EQ(wider.occludedPixelsAt(0.6), rgb.rows * rgb.cols);

  EXPECT_THROW(OcclusionEstimator(nullptr), InvalidArgumentError);
  EXPECT_THROW(OcclusionEstimator(model, 1.0), InvalidArgumentError);
  EXPECT_THROW(OcclusionEstimator(model, 0.0), InvalidArgumentError);
}

}  // namespace
}  // namespace learning
}  // namespace occlusion_env
