// occlusion_train: trains the multi-task network (learning/training.hpp) on a BOP dataset
// written by occlusion_dataset; resumable (re-run the same command), best model by validation IoU.
//   occlusion_train --data data/train_sweethome3d --out runs/unet64 --variant unet --size 64
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/package_paths.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/eval/progress.hpp"
#include "occlusion_env/eval/subprocess.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/training.hpp"
#include "occlusion_env/tools/arguments.hpp"

namespace {

constexpr const char* kUsage = R"(Usage: occlusion_train --data DIR --out RUN_DIR [options]
Trains the multi-task U-Net (occlusion map, gradient and escape directions) on a dataset made by
occlusion_dataset. Every epoch: validation on the dataset's validation scenes, a checkpoint in
RUN_DIR (re-run the same command to resume), log.csv and curves.png; RUN_DIR/best.pt (+ .json) is
the model with the best validation IoU.

Options:
  --data DIR             the dataset (occlusion_dataset --out DIR); repeatable: every dataset's
                         training and validation scenes are used (its own split), so one made
                         with --validation 0 (e.g. --no-oracle, many scenes) only adds training
                         frames; the manifests record the first as "dataset"
  --out RUN_DIR          where checkpoints, logs and the best model go
  --variant V            unet | r_unet | sr_unet | sar_unet (default unet)
  --size N               network input size [px], multiple of 32 (default 64)
  --base N               channels of the first stage (default 8)
  --epochs N             (default 15)
  --batch N              (default 32)
  --lr X                 AdamW learning rate, cosine-annealed (default 0.001)
  --weight-decay X       (default 1e-5)
  --direction-loss L     mse | smooth_l1 (beta 0.01; the paper's -L1 variant) (default mse)
  --dice-weight X        beta_1 (default 1)
  --direction-weight X   beta_2 (default 1)
  --bce-weight X         adds X times a pixel-wise binary cross-entropy on the occlusion map to
                         the paper's loss (default 0: the paper's loss)
  --no-augment           no colour jitter or flips
  --init-from MODEL      start from MODEL's weights (a best.pt of an earlier run of the same
                         network) instead of random ones: a new cosine schedule and a fresh
                         optimizer on them (a warm restart); recorded in the manifests
  --max-scenes N         use only the first N scenes of the dataset
  --seed S               (default 1)
  --threads N            libtorch threads (default: all cores)
  --check M              instead: the figures of model M (as validation's) on every frame of
                         the --data datasets, which must be other scenes than M's training and
                         validation ones (e.g. a dataset of seeds 950000 on, --validation 0)
  --bench-inference M    instead: time one learned step's inference with model M (input from a
                         256 x 256 observation, batch 1, one thread) and exit
  --help                 this text
)";

// Median time of one learned step's inference, NetworkDirectionAgent::act: the input from a
// 256 x 256 observation, the encoder and the escape head (batch 1, one thread).
int benchInference(const std::string& model_path) {
  using namespace occlusion_env;
  try {
    torch::set_num_threads(1);
    EnvironmentOptions options;
    Environment environment(options);
    const StepResult start = environment.reset(1000000);
    auto model = std::make_shared<learning::LoadedModel>(learning::loadModel(model_path));
    learning::NetworkDirectionAgent agent(model, learning::DirectionHead::kEscape);
    std::vector<double> milliseconds;
    for (int i = 0; i < 220; ++i) {
      const auto begin = std::chrono::steady_clock::now();
      agent.act(*start.observation, start.info);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin)
              .count();
      if (i >= 20) milliseconds.push_back(ms);  // after warm-up
    }
    std::sort(milliseconds.begin(), milliseconds.end());
    std::cout << "inference of " << model_path << " (" << model->network->config().input_size
              << " px input from 256 x 256, batch 1, 1 thread, BLAS "
              << learning::loadedBlasLibrary() << "): median " << std::fixed << std::setprecision(2)
              << milliseconds[milliseconds.size() / 2] << " ms, p90 "
              << milliseconds[milliseconds.size() * 9 / 10] << " ms over 200 steps\n";
  } catch (const std::exception& error) {
    std::cerr << "occlusion_train: " << error.what() << "\n";
    return 1;
  }
  return 0;
}

// Validation's figures of a model on every frame of datasets it was neither trained nor chosen
// on, printed and written as JSON beside the model (<model>.check.json).
int checkModel(const std::string& model_path, const std::vector<std::string>& data_dirs,
               int threads) {
  using namespace occlusion_env;
  try {
    learning::setLibtorchThreads(threads);
    learning::LoadedModel model = learning::loadModel(model_path);
    const int size = model.network->config().input_size;
    std::cerr << "occlusion_train: reading " << data_dirs.front() << " at " << size << " px...\n";
    const learning::Samples frames = learning::loadCheckFrames(data_dirs, size, model.manifest);
    const std::string loss =
        model.manifest.value("training", nlohmann::json::object()).value("direction_loss", "mse");
    const learning::EpochMetrics m = learning::evaluate(model.network, frames, 64, loss);
    nlohmann::json result = {{"model", model_path},
                             {"datasets", data_dirs},
                             {"frames", frames.size()},
                             {"figures", m.toJson()}};
    for (const char* unused :
         {"epoch", "learning_rate", "train_loss", "seconds", "images_per_second"}) {
      result["figures"].erase(unused);
    }
    const std::string out =
        std::filesystem::path(model_path).replace_extension(".check.json").string();
    std::ofstream(out) << result.dump(2) << '\n';
    std::cout << std::fixed << std::setprecision(2) << model_path << " on " << frames.size()
              << " frames: IoU " << 100.0 * m.val_iou << " %, pixel acc "
              << 100.0 * m.val_pixel_accuracy << " %, dice loss " << std::setprecision(4)
              << m.val_dice_loss << ", gradient " << std::setprecision(1)
              << m.val_gradient_angle_deg << " deg, escape " << m.val_escape_angle_deg << " deg ("
              << out << ")\n";
  } catch (const std::exception& error) {
    std::cerr << "occlusion_train: " << error.what() << "\n";
    return 1;
  }
  return 0;
}

// Trains on the datasets in `data_dirs` into `run_dir` (resuming a run there), with a progress
// bar, each epoch's figures and the curves' plot; the exit status.
int runTraining(const occlusion_env::learning::TrainingOptions& options,
                const std::vector<std::string>& data_dirs, const std::string& run_dir,
                int max_scenes) {
  using namespace occlusion_env;
  try {
    options.validate();
    if (learning::referenceBlasLoaded()) {
      std::cerr << "occlusion_train: WARNING: libtorch runs on the reference BLAS ("
                << learning::loadedBlasLibrary()
                << "): convolutions are 5-8x slower. Install libopenblas0-openmp "
                   "(scripts/install_deps.sh does).\n";
    }
    std::cerr << "occlusion_train: reading " << data_dirs.front()
              << (data_dirs.size() > 1 ? " and " + std::to_string(data_dirs.size() - 1) + " more"
                                       : std::string())
              << " at " << options.network.input_size << " px...\n";
    const learning::TrainingData data =
        learning::loadTrainingData(data_dirs, options.network.input_size, max_scenes);
    std::cerr << "occlusion_train: " << data.train.size() << " training and "
              << data.validation.size() << " validation frames; " << options.network.variant << ", "
              << options.epochs << " epochs, checkpoints in " << run_dir << "\n";
    std::unique_ptr<eval::ProgressBar> bar;
    int done = 0;  // batches in this run (a resumed run starts later)
    learning::TrainingCallbacks callbacks;
    callbacks.on_batch = [&](int epoch, int batch, int batches) {
      if (!bar) {
        bar = std::make_unique<eval::ProgressBar>(std::cerr, (options.epochs - epoch + 1) * batches,
                                                  "training");
        bar->update(0, "");
      }
      ++done;
      if (batch % 10 == 0 || batch == batches) {
        bar->update(done, "epoch " + std::to_string(epoch) + "/" + std::to_string(options.epochs));
      }
    };
    callbacks.on_epoch = [&](const learning::EpochMetrics& m) {
      std::cerr << "\nepoch " << m.epoch << ": train loss " << std::fixed << std::setprecision(4)
                << m.train_loss << ", val IoU " << 100.0 * m.val_iou << " %, pixel acc "
                << 100.0 * m.val_pixel_accuracy << " %, dice loss " << m.val_dice_loss
                << ", gradient MSE " << m.val_gradient_mse << " (" << std::setprecision(1)
                << m.val_gradient_angle_deg << " deg), escape MSE " << std::setprecision(4)
                << m.val_escape_mse << " (" << std::setprecision(1) << m.val_escape_angle_deg
                << " deg), " << std::setprecision(0) << m.images_per_second << " img/s\n";
    };
    const auto history = learning::train(data, options, run_dir, callbacks);
    if (bar) bar->finish();
    const std::string script = packageShareDirectory() + "/scripts/plot_training.py";
    const std::string log = (std::filesystem::path(run_dir) / "log.csv").string();
    if (eval::runProgram({"/usr/bin/python3", script, log}, "", "") != 0) {
      std::cerr << "occlusion_train: plotting the curves failed (python3-matplotlib?)\n";
    }
    double best = 0.0;
    for (const auto& m : history) best = std::max(best, m.val_iou);
    std::cout << "occlusion_train: done, " << history.size() << " epochs; best validation IoU "
              << std::fixed << std::setprecision(2) << 100.0 * best << " % in " << run_dir
              << "/best.pt\n";
  } catch (const std::exception& error) {
    std::cerr << "\nocclusion_train: " << error.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  learning::TrainingOptions options;
  std::vector<std::string> data_dirs;
  std::string run_dir;
  int max_scenes = 0;
  std::string bench_model;
  std::string check_model;
  try {
    tools::ArgumentReader reader(argc, argv);
    while (reader.next()) {
      const std::string& flag = reader.flag();
      if (flag == "--help" || flag == "-h") {
        std::cout << kUsage;
        return 0;
      } else if (flag == "--data") {
        data_dirs.push_back(reader.text());
      } else if (flag == "--out") {
        run_dir = reader.text();
      } else if (flag == "--variant") {
        options.network.variant = reader.text();
      } else if (flag == "--size") {
        options.network.input_size = static_cast<int>(reader.integer(32, 512));
      } else if (flag == "--base") {
        options.network.base_channels = static_cast<int>(reader.integer(1, 64));
      } else if (flag == "--epochs") {
        options.epochs = static_cast<int>(reader.integer(1, 10000));
      } else if (flag == "--batch") {
        options.batch_size = static_cast<int>(reader.integer(2, 4096));
      } else if (flag == "--lr") {
        options.learning_rate = reader.number(1e-7, 1.0);
      } else if (flag == "--weight-decay") {
        options.weight_decay = reader.number(0.0, 1.0);
      } else if (flag == "--direction-loss") {
        options.direction_loss = reader.text();
      } else if (flag == "--dice-weight") {
        options.dice_weight = reader.number(0.0, 1000.0);
      } else if (flag == "--direction-weight") {
        options.direction_weight = reader.number(0.0, 1000.0);
      } else if (flag == "--bce-weight") {
        options.bce_weight = reader.number(0.0, 1000.0);
      } else if (flag == "--no-augment") {
        options.augment = false;
      } else if (flag == "--init-from") {
        options.init_from = reader.text();
      } else if (flag == "--max-scenes") {
        max_scenes = static_cast<int>(reader.integer(1, 10000000));
      } else if (flag == "--seed") {
        options.seed = reader.unsignedInteger();
      } else if (flag == "--check") {
        check_model = reader.text();
      } else if (flag == "--bench-inference") {
        bench_model = reader.text();
      } else if (flag == "--threads") {
        options.threads = static_cast<int>(reader.integer(0, 256));
      } else {
        reader.unknown();
      }
    }
    if (!check_model.empty() && data_dirs.empty()) {
      throw tools::ArgumentError("--check needs --data");
    }
    if (bench_model.empty() && check_model.empty() && (data_dirs.empty() || run_dir.empty())) {
      throw tools::ArgumentError("--data and --out are required");
    }
  } catch (const tools::ArgumentError& error) {
    std::cerr << "occlusion_train: " << error.what() << "\n" << kUsage;
    return 2;
  }
  if (!bench_model.empty()) return benchInference(bench_model);
  if (!check_model.empty()) return checkModel(check_model, data_dirs, options.threads);
  return runTraining(options, data_dirs, run_dir, max_scenes);
}
