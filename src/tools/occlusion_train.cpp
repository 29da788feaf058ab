// occlusion_train: trains the multi-task network (learning/training.hpp) on a BOP dataset
// written by occlusion_dataset; resumable (re-run the same command), best model by validation IoU.
//   occlusion_train --data data/train_sweethome3d --out runs/unet64 --variant unet --size 64
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/package_paths.hpp"
#include "occlusion_env/common/statistics.hpp"
#include "occlusion_env/common/text_file.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/eval/progress.hpp"
#include "occlusion_env/eval/subprocess.hpp"
#include "occlusion_env/learning/check_montage.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/training.hpp"
#include "occlusion_env/tools/cli_options.hpp"

namespace {

using occlusion_env::OptionSpec;
using occlusion_env::OptionTable;

/// The tool's own options; the training's come from trainingOptionTable() and
/// networkConfigTable().
struct Arguments {
  occlusion_env::learning::TrainingOptions options;
  std::vector<std::string> data_dirs;
  std::string run_dir;
  int max_scenes = 0;  // 0: all
  std::string check_model;
  std::string montage_path;  // with --check: the contact sheet's PNG; "": none
  int montage_frames = 6;
  // With --check: the IoU also at these occlusion probability thresholds (0.5: validation's).
  std::vector<double> check_probabilities = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7};
  std::string versus_dir;  // with --check: a second dataset, and the gap between the two IoUs
  std::string bench_model;
  std::string half_precision_model;  // instead: its float16 copy written to --out
  std::string eight_bit_model;       // instead: its 8-bit copy written to --out
};

const OptionTable<Arguments>& argumentTable() {
  static const auto table =
      OptionTable<Arguments>()
          .add("data", &Arguments::data_dirs,
               OptionSpec("the dataset (occlusion_dataset --out DIR); repeatable: every "
                          "dataset's training and validation scenes are used (its own split), so "
                          "one made with --validation 0 only adds training frames; the manifests "
                          "record the first as \"dataset\"")
                   .repeatable())
          .add("out", &Arguments::run_dir,
               OptionSpec("RUN_DIR: where checkpoints, logs and the best model go; with --check: "
                          "the JSON file of the figures (default: beside the model, "
                          "<model>.check.json); with --half-precision-copy: the new model file"))
          .add(
              "max_scenes", &Arguments::max_scenes,
              OptionSpec("use only the first N scenes of each dataset; 0 = all").range(0, 10000000))
          .add("check", &Arguments::check_model,
               OptionSpec("instead: the figures of this model (as validation's) on every frame of "
                          "the --data datasets, which must be other scenes than its training and "
                          "validation ones (e.g. a dataset of seeds 950000 on, --validation 0), "
                          "and the escape error by the oracle's steps from each frame to a clear "
                          "view"))
          .add("montage", &Arguments::montage_path,
               OptionSpec("with --check: also a PNG contact sheet here: a row per world and depth "
                          "sensor, --montage-frames frames of each (spread over its frames) as the "
                          "network sees them, the label green, the estimate red, both yellow, the "
                          "depth beside (learning/check_montage.hpp)"))
          .add("montage_frames", &Arguments::montage_frames,
               OptionSpec("with --montage: frames per row").range(1, 32))
          .add("probabilities", &Arguments::check_probabilities,
               OptionSpec("with --check: also the IoU with the occlusion map thresholded at these "
                          "probabilities (validation's is 0.5)")
                   .range(1e-6, 1.0 - 1e-6))
          .add("versus", &Arguments::versus_dir,
               OptionSpec("with --check: also the IoU on this dataset (e.g. the randomised frames "
                          "of the same scene seeds) and the gap, --data's IoU minus this one's, "
                          "with its 95 % interval by a bootstrap paired by scene"))
          .add("bench_inference", &Arguments::bench_model,
               OptionSpec("instead: time one learned step's inference with this model (input from "
                          "a 256 x 256 observation, batch 1, one thread) and exit"))
          .add("half_precision_copy", &Arguments::half_precision_model,
               OptionSpec("instead: write this model with its weights stored in float16 (half "
                          "the file, for shipping; loaded and run in float32) to --out "
                          "(NEW.pt, its manifest beside it) and exit"))
          .add("eight_bit_copy", &Arguments::eight_bit_model,
               OptionSpec("instead: write this model with each layer's weights stored as 8-bit "
                          "codes per output channel (a quarter of the file, for shipping; loaded "
                          "and run in float32, each weight within half a code's step) to --out "
                          "(NEW.pt, its manifest beside it) and exit"));
  return table;
}

// The flags that write a model's compact copy to --out instead of training.
struct CompactCopyFlag {
  std::string Arguments::*source;
  const char* flag;
  occlusion_env::learning::WeightStorage storage;
  const char* weights;  // for the message
};
const CompactCopyFlag kCompactCopyFlags[] = {
    {&Arguments::half_precision_model, "--half-precision-copy",
     occlusion_env::learning::WeightStorage::kFloat16, "float16"},
    {&Arguments::eight_bit_model, "--eight-bit-copy",
     occlusion_env::learning::WeightStorage::kUint8, "8-bit"}};

/// The rules between the flags; `probabilities_given`: --probabilities was on the command line
/// (it has a default, so `args` cannot tell).
void checkArguments(const Arguments& args, bool probabilities_given) {
  if (!args.check_model.empty() && args.data_dirs.empty()) {
    throw CLI::ValidationError("--check needs --data");
  }
  for (const auto& [flag, given] :
       {std::pair<const char*, bool>{"--montage", !args.montage_path.empty()},
        {"--versus", !args.versus_dir.empty()},
        {"--probabilities", probabilities_given}}) {
    if (given && args.check_model.empty()) {
      throw CLI::ValidationError(std::string(flag) + " needs --check");
    }
  }
  int copies = 0;
  for (const CompactCopyFlag& copy : kCompactCopyFlags) {
    if ((args.*copy.source).empty()) continue;
    ++copies;
    if (args.run_dir.empty())
      throw CLI::ValidationError(std::string(copy.flag) + " needs --out NEW.pt");
  }
  if (copies > 1) {
    throw CLI::ValidationError("--half-precision-copy and --eight-bit-copy: give one of them");
  }
  if (args.bench_model.empty() && args.check_model.empty() && copies == 0 &&
      (args.data_dirs.empty() || args.run_dir.empty())) {
    throw CLI::ValidationError("--data and --out are required");
  }
}

// Median time of one learned step's inference, NetworkDirectionAgent::act: the input from a
// 256 x 256 observation, the encoder and the escape head (batch 1, one thread).
int benchInference(const std::string& model_path) {
  using namespace occlusion_env;
  torch::set_num_threads(1);
  EnvironmentOptions options;
  Environment environment(options);
  const StepResult start = environment.reset(1000000);
  auto model = std::make_shared<learning::LoadedModel>(learning::loadModel(model_path));
  learning::NetworkDirectionAgent agent(model, learning::DirectionHead::kEscape);
  std::vector<double> milliseconds;
  for (int i = 0; i < 220; ++i) {
    const auto begin = std::chrono::steady_clock::now();
    agent.act(rigObservationOf(start));
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
    if (i >= 20) milliseconds.push_back(ms);  // after warm-up
  }
  std::cout << "inference of " << model_path << " (" << model->network->config().input_size
            << " px input from 256 x 256, batch 1, 1 thread, BLAS " << learning::loadedBlasLibrary()
            << "): median " << std::fixed << std::setprecision(2) << median(milliseconds)
            << " ms, p90 " << percentile(milliseconds, 0.9) << " ms over 200 steps\n";
  return 0;
}

// escapeErrorsByOracleSteps()' rows as a table on stdout, after the check's summary line.
void printEscapeErrors(const nlohmann::json& rows) {
  std::cout << "escape error by the oracle's steps from the frame to a clear view (shortest: the "
               "share of moves as short as the oracle's, where recorded):\n"
            << "  steps       frames   mean   median   > 45 deg   > 90 deg   shortest\n";
  for (const nlohmann::json& row : rows) {
    std::cout << "  " << std::left << std::setw(10) << row["oracle_steps"].get<std::string>()
              << std::right << std::setw(8) << row["frames"].get<int64_t>() << std::fixed
              << std::setprecision(1) << std::setw(7) << row["mean_deg"].get<double>()
              << std::setw(9) << row["median_deg"].get<double>() << std::setw(10)
              << 100.0 * row["share_over_45_deg"].get<double>() << " %" << std::setw(9)
              << 100.0 * row["share_over_90_deg"].get<double>() << " %";
    if (row.contains("share_shortest")) {
      std::cout << std::setw(9) << 100.0 * row["share_shortest"].get<double>() << " %";
    }
    std::cout << '\n';
  }
}

// An IoU's interval as "low-high %", one decimal.
std::string intervalText(const nlohmann::json& interval) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(1) << 100.0 * interval[0].get<double>() << "-"
       << 100.0 * interval[1].get<double>() << " %";
  return text.str();
}

// The check's figures by the world and depth sensor the frames were seen under.
void printConditions(const nlohmann::json& rows) {
  std::cout << "by world and depth sensor:\n"
            << "  world, depth sensor           frames  scenes     IoU   95 % over scenes  "
               "precision  recall  false alarms <= 1 px, <= 3 px from the label   escape\n";
  for (const nlohmann::json& row : rows) {
    std::cout << "  " << std::left << std::setw(28) << row["condition"].get<std::string>()
              << std::right << std::setw(8) << row["frames"].get<int64_t>() << std::setw(8)
              << row["scenes"].get<int>() << std::fixed << std::setprecision(1) << std::setw(7)
              << 100.0 * row["val_iou"].get<double>() << " %" << std::setw(16)
              << intervalText(row["val_iou_95"]) << std::setw(11)
              << 100.0 * row["precision"].get<double>() << " %" << std::setw(6)
              << 100.0 * row["recall"].get<double>() << " %";
    if (row.contains("false_positives_within_1px")) {
      std::cout << std::setw(20) << 100.0 * row["false_positives_within_1px"].get<double>() << " %"
                << std::setw(7) << 100.0 * row["false_positives_within_3px"].get<double>() << " %";
    } else {
      std::cout << std::setw(20) << "-"
                << "  " << std::setw(7) << "-"
                << "  ";  // none
    }
    if (row.contains("mean_escape_deg")) {  // under its heading, past the false alarms' one
      std::cout << std::setw(22) << row["mean_escape_deg"].get<double>() << " deg";
    }
    std::cout << '\n';
  }
}

// Validation's figures of a model on every frame of datasets it was neither trained nor chosen
// on, printed and written as JSON to `out_path` ("": beside the model, <model>.check.json).
int checkModel(const std::string& model_path, const std::vector<std::string>& data_dirs,
               int threads, double mask_coverage, const std::string& out_path,
               const std::string& montage_path, int montage_frames,
               const std::vector<double>& probabilities, const std::string& versus_dir) {
  using namespace occlusion_env;
  learning::setLibtorchThreads(threads);
  learning::LoadedModel model = learning::loadModel(model_path);
  const int size = model.network->config().input_size;
  std::cerr << "occlusion_train: reading " << data_dirs.front() << " at " << size << " px...\n";
  std::vector<std::string> conditions;
  std::vector<std::uint64_t> scene_seeds;
  const learning::Samples frames =
      learning::loadCheckFrames(data_dirs, model.network->config().inputFormat(), model.manifest,
                                mask_coverage, &conditions, &scene_seeds);
  const std::string loss =
      model.manifest.value("training", nlohmann::json::object()).value("direction_loss", "mse");
  torch::Tensor escape_errors_deg, escape_shortest, occlusion_counts;
  learning::IouByProbability by_probability{probabilities, {}};
  const learning::EpochMetrics m =
      learning::evaluate(model.network, frames, 64, loss, &escape_errors_deg, &escape_shortest,
                         &occlusion_counts, &by_probability);
  nlohmann::json result = {{"model", model_path},
                           {"datasets", data_dirs},
                           {"frames", frames.size()},
                           {"figures", m.toJson()}};
  // Labels at another coverage than the paper's are other labels: said where the figures are.
  if (mask_coverage != learning::kPaperMaskCoverage) result["mask_coverage"] = mask_coverage;
  for (const char* unused :
       {"epoch", "learning_rate", "train_loss", "seconds", "images_per_second"}) {
    result["figures"].erase(unused);
  }
  // Frames made without the oracle have no escape label: the escape figures are not measured
  // (null), rather than 0.
  const bool escape_labelled = frames.escape_valid.sum().item<double>() > 0.0;
  if (!escape_labelled) {
    for (auto& [key, value] : result["figures"].items()) {
      if (key.rfind("val_escape", 0) == 0) value = nullptr;
    }
  }
  // How far the IoU would move on other scenes: a check set of few scenes is a noisy figure.
  std::vector<int64_t> every_frame(static_cast<std::size_t>(frames.size()));
  std::iota(every_frame.begin(), every_frame.end(), int64_t{0});
  const learning::IouInterval interval =
      learning::sceneBootstrapIou(occlusion_counts, scene_seeds, every_frame);
  result["scenes"] = interval.scenes;
  result["figures"]["val_iou_95"] = {interval.low, interval.high};
  result["escape_by_oracle_steps"] =
      learning::escapeErrorsByOracleSteps(escape_errors_deg, frames.oracle_steps, escape_shortest);
  // Frames of several worlds or depth sensors (a randomised set): the figures of each.
  const nlohmann::json by_condition =
      learning::figuresByCondition(conditions, occlusion_counts, escape_errors_deg, scene_seeds);
  if (by_condition.size() > 1) result["by_condition"] = by_condition;
  result["iou_by_probability"] = nlohmann::json::array();
  for (std::size_t i = 0; i < by_probability.ious.size(); ++i) {
    result["iou_by_probability"].push_back(
        {{"probability", probabilities[i]}, {"val_iou", by_probability.ious[i]}});
  }
  // The same scenes under another camera: its IoU, and the gap paired by scene.
  learning::IouGap gap;
  learning::IouInterval versus_interval;
  double versus_iou = 0.0;
  if (!versus_dir.empty()) {
    std::vector<std::uint64_t> versus_seeds;
    const learning::Samples versus_frames =
        learning::loadCheckFrames({versus_dir}, model.network->config().inputFormat(),
                                  model.manifest, mask_coverage, nullptr, &versus_seeds);
    torch::Tensor versus_counts;
    versus_iou =
        learning::evaluate(model.network, versus_frames, 64, loss, nullptr, nullptr, &versus_counts)
            .val_iou;
    std::vector<int64_t> every_versus_frame(static_cast<std::size_t>(versus_frames.size()));
    std::iota(every_versus_frame.begin(), every_versus_frame.end(), int64_t{0});
    versus_interval = learning::sceneBootstrapIou(versus_counts, versus_seeds, every_versus_frame);
    gap =
        learning::sceneBootstrapIouGap(occlusion_counts, scene_seeds, versus_counts, versus_seeds);
    result["versus"] = {{"dataset", versus_dir},
                        {"frames", versus_frames.size()},
                        {"scenes", versus_interval.scenes},
                        {"val_iou", versus_iou},
                        {"val_iou_95", {versus_interval.low, versus_interval.high}},
                        {"gap", gap.gap},
                        {"gap_95", {gap.low, gap.high}},
                        {"paired_scenes", gap.scenes}};
  }
  const std::string out =
      out_path.empty() ? std::filesystem::path(model_path).replace_extension(".check.json").string()
                       : out_path;
  writeTextFile(out, result.dump(2) + "\n");
  std::cout << std::fixed << std::setprecision(2) << model_path << " on " << frames.size()
            << " frames"
            << (mask_coverage != learning::kPaperMaskCoverage
                    ? " (labels at coverage " + std::to_string(mask_coverage).substr(0, 5) + ")"
                    : std::string())
            << ": IoU " << 100.0 * m.val_iou << " % (95 % over " << interval.scenes
            << " scenes: " << 100.0 * interval.low << "-" << 100.0 * interval.high
            << " %), pixel acc " << 100.0 * m.val_pixel_accuracy << " %, dice loss "
            << std::setprecision(4) << m.val_dice_loss << ", gradient " << std::setprecision(1)
            << m.val_gradient_angle_deg << " deg, ";
  // Frames made without the oracle have no escape label: no error, rather than 0 deg.
  if (escape_labelled) {
    std::cout << "escape " << m.val_escape_angle_deg << " deg"
              << (m.val_escape_bins_angle_deg > 0.0
                      ? " (bins " + std::to_string(m.val_escape_bins_angle_deg).substr(0, 5) +
                            " deg)"
                      : std::string());
  } else {
    std::cout << "no escape labels (made with --no-oracle)";
  }
  std::cout << " (" << out << ")\n";
  const std::vector<double>& ious = by_probability.ious;
  if (!ious.empty()) {
    std::cout << "IoU with the map thresholded at probability:";
    for (std::size_t i = 0; i < ious.size(); ++i) {
      std::cout << (i ? ", " : " ") << std::setprecision(2) << probabilities[i] << " "
                << std::setprecision(1) << 100.0 * ious[i] << " %";
    }
    std::cout << '\n';
  }
  if (!versus_dir.empty()) {
    std::cout << "versus " << versus_dir << ": IoU " << std::setprecision(2) << 100.0 * versus_iou
              << " % (95 % over " << versus_interval.scenes
              << " scenes: " << 100.0 * versus_interval.low << "-" << 100.0 * versus_interval.high
              << " %); gap " << 100.0 * gap.gap << " points (95 %, paired over " << gap.scenes
              << " scenes: " << 100.0 * gap.low << " to " << 100.0 * gap.high << ")\n";
  }
  if (escape_labelled) printEscapeErrors(result["escape_by_oracle_steps"]);
  if (result.contains("by_condition")) printConditions(result["by_condition"]);
  if (!montage_path.empty()) {
    const cv::Mat sheet = learning::checkMontage(model.network, frames, conditions, montage_frames);
    if (!cv::imwrite(montage_path, sheet)) {
      throw InvalidArgumentError("cannot write the montage " + quoted(montage_path));
    }
    std::cout << "montage: " << montage_path << '\n';
  }
  return 0;
}

/// Prints a progress bar over the batches of this run (a resumed run starts later) and each
/// epoch's figures.
occlusion_env::learning::TrainingCallbacks progressReport(
    int epochs, std::unique_ptr<occlusion_env::eval::ProgressBar>& bar) {
  using namespace occlusion_env;
  learning::TrainingCallbacks callbacks;
  callbacks.on_batch = [&bar, epochs, done = 0](int epoch, int batch, int batches) mutable {
    if (!bar) {
      bar = std::make_unique<eval::ProgressBar>(std::cerr, (epochs - epoch + 1) * batches,
                                                "training");
      bar->update(0, "");
    }
    ++done;
    if (batch % 10 == 0 || batch == batches) {
      bar->update(done, "epoch " + std::to_string(epoch) + "/" + std::to_string(epochs));
    }
  };
  callbacks.on_epoch = [](const learning::EpochMetrics& m) {
    std::cerr << "\nepoch " << m.epoch << ": train loss " << std::fixed << std::setprecision(4)
              << m.train_loss << ", val IoU " << 100.0 * m.val_iou << " %, pixel acc "
              << 100.0 * m.val_pixel_accuracy << " %, dice loss " << m.val_dice_loss
              << ", gradient MSE " << m.val_gradient_mse << " (" << std::setprecision(1)
              << m.val_gradient_angle_deg << " deg), escape MSE " << std::setprecision(4)
              << m.val_escape_mse << " (" << std::setprecision(1) << m.val_escape_angle_deg
              << " deg";
    if (m.val_escape_bins_angle_deg > 0.0) {
      std::cerr << "; bins " << m.val_escape_bins_angle_deg << " deg";
    }
    std::cerr << "), " << std::setprecision(0) << m.images_per_second << " img/s\n";
  };
  return callbacks;
}

int train(const Arguments& args) {
  using namespace occlusion_env;
  const learning::TrainingOptions& options = args.options;
  options.validate();
  if (learning::referenceBlasLoaded()) {
    std::cerr << "occlusion_train: WARNING: libtorch runs on the reference BLAS ("
              << learning::loadedBlasLibrary()
              << "): convolutions are 5-8x slower. Install libopenblas0-openmp "
                 "(scripts/install_deps.sh does).\n";
  }
  const std::vector<std::string>& data_dirs = args.data_dirs;
  std::cerr << "occlusion_train: reading " << data_dirs.front()
            << (data_dirs.size() > 1 ? " and " + std::to_string(data_dirs.size() - 1) + " more"
                                     : std::string())
            << " at " << options.network.input_size << " px...\n";
  const learning::TrainingData data =
      learning::loadTrainingData(data_dirs, options.network.inputFormat(), args.max_scenes,
                                 options.negatives, options.seed, options.mask_coverage);
  std::cerr << "occlusion_train: " << data.train.size() << " training and "
            << data.validation.size() << " validation frames; " << options.network.variant << ", "
            << options.epochs << " epochs, checkpoints in " << args.run_dir << "\n";
  if (options.escape_bin_targets == "shortest_moves") {
    std::cerr << "occlusion_train: " << (data.train.shortest_moves.sum(1) > 0).sum().item<int64_t>()
              << " of " << data.train.size()
              << " training frames record their shortest first moves (the others: the bump "
                 "around the label)\n";
  }
  std::unique_ptr<eval::ProgressBar> bar;
  const auto history =
      learning::train(data, options, args.run_dir, progressReport(options.epochs, bar));
  if (bar) bar->finish();
  const std::string script = packageShareDirectory() + "/scripts/plot_training.py";
  const std::string log = (std::filesystem::path(args.run_dir) / "log.csv").string();
  if (eval::runProgram({"/usr/bin/python3", script, log}, "", "") != 0) {
    std::cerr << "occlusion_train: plotting the curves failed (python3-matplotlib?)\n";
  }
  double best = 0.0;
  for (const auto& m : history) best = std::max(best, m.val_iou);
  std::cout << "occlusion_train: done, " << history.size() << " epochs; best validation IoU "
            << std::fixed << std::setprecision(2) << 100.0 * best << " % in " << args.run_dir
            << "/best.pt\n";
  return 0;
}

int run(const Arguments& args) {
  if (!args.bench_model.empty()) return benchInference(args.bench_model);
  for (const CompactCopyFlag& copy : kCompactCopyFlags) {
    const std::string& source = args.*copy.source;
    if (source.empty()) continue;
    occlusion_env::learning::saveCompactCopy(source, args.run_dir, copy.storage);
    std::cout << "occlusion_train: wrote " << args.run_dir << " (" << copy.weights << " weights of "
              << source << ") and its manifest\n";
    return 0;
  }
  if (!args.check_model.empty()) {
    return checkModel(args.check_model, args.data_dirs, args.options.threads,
                      args.options.mask_coverage, args.run_dir, args.montage_path,
                      args.montage_frames, args.check_probabilities, args.versus_dir);
  }
  return train(args);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  Arguments args;
  CLI::App app(
      "Trains the multi-task U-Net (occlusion map, gradient and escape directions) on a dataset "
      "made by\nocclusion_dataset. Every epoch: validation on the dataset's validation scenes, a "
      "checkpoint in\nRUN_DIR (re-run the same command to resume), log.csv and curves.png; "
      "RUN_DIR/best.pt (+ .json) is\nthe model with the best validation IoU.",
      "occlusion_train");
  tools::addOptionFlags(app, argumentTable(), args, {"data", "out"});
  tools::addOptionFlags(app, learning::networkConfigTable(), args.options.network);
  tools::addOptionFlags(app, learning::trainingOptionTable(), args.options);
  tools::addOptionFlags(app, argumentTable(), args,
                        {"max_scenes", "check", "montage", "montage_frames", "probabilities",
                         "versus", "bench_inference", "half_precision_copy", "eight_bit_copy"});
  app.callback([&args, &app] { checkArguments(args, app.count("--probabilities") > 0); });
  return tools::parseAndRun(app, argc, argv, [&args] { return run(args); });
}
