#include "occlusion_env/report/model_report.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>
#include <vector>

namespace occlusion_env {
namespace report {

namespace fs = std::filesystem;

namespace {

// The manifests (*.json) in `folder` of `kind` ("multitask_unet" for those written before kinds
// existed) that carry validation figures, in file-name order; unreadable files are left out.
std::vector<nlohmann::json> manifestsIn(const fs::path& folder, const std::string& kind) {
  std::vector<fs::path> paths;
  if (fs::is_directory(folder)) {
    for (const auto& entry : fs::directory_iterator(folder)) {
      if (entry.path().extension() == ".json") paths.push_back(entry.path());
    }
  }
  std::sort(paths.begin(), paths.end());
  std::vector<nlohmann::json> manifests;
  for (const fs::path& path : paths) {
    std::ifstream in(path);
    try {
      nlohmann::json manifest = nlohmann::json::parse(in);
      if (manifest.value("kind", "multitask_unet") == kind && manifest.contains("validation")) {
        manifest["manifest_file"] = path.filename().string();
        manifests.push_back(std::move(manifest));
      }
    } catch (const std::exception&) {
    }
  }
  return manifests;
}

// The shipped models' manifests (models/*.json) of `kind`.
std::vector<nlohmann::json> shippedManifests(const EvalOptions& cl, const std::string& kind) {
  return manifestsIn(fs::path(cl.source_dir) / "models", kind);
}

// One row of the network table: a model's best-epoch validation figures (its manifest).
void networkRow(std::ostringstream& md, const std::string& name, const nlohmann::json& manifest) {
  const nlohmann::json& v = manifest["validation"];
  const nlohmann::json& net = manifest["network"];
  const nlohmann::json training = manifest.value("training", nlohmann::json::object());
  const nlohmann::json run = manifest.value("run", nlohmann::json::object());
  const std::string loss = training.value("direction_loss", "mse");
  // The validation's direction figure is the training's direction loss: SmoothL1 for -L1 runs.
  const std::string loss_note = loss == "smooth_l1" ? " (SmoothL1)" : "";
  md << std::fixed << "| " << name << " | " << net.value("variant", "?")
     << (loss == "smooth_l1" ? "-L1" : "")
     << (training.value("bce_weight", 0.0) > 0.0 ? " +BCE" : "") << " | "
     << net.value("input_size", 0) << " | ";
  // A warm restart (--init-from) continues the epochs and minutes of the run it started from.
  const nlohmann::json start = manifest.value("initialised_from", nlohmann::json::object());
  const std::string before =
      start.contains("epoch")
          ? std::to_string(start.value("epochs_before", start.value("epoch", 0))) + "+"
          : "";
  md << before << manifest.value("epoch", 0) << " / " << before << training.value("epochs", 0)
     << " | ";
  const nlohmann::json start_run = start.value("run", nlohmann::json::object());
  if (run.contains("minutes") && start_run.contains("minutes")) {
    md << std::setprecision(0) << start_run.value("minutes", 0.0) << "+"
       << run.value("minutes", 0.0) << " min | ";
  } else if (run.contains("minutes")) {
    md << std::setprecision(0) << run.value("minutes", 0.0) << " min | ";
  } else {
    md << "- | ";
  }
  md << std::setprecision(3) << v.value("val_dice_loss", 0.0) << " | " << std::setprecision(2)
     << 100.0 * v.value("val_pixel_accuracy", 0.0) << " % | " << 100.0 * v.value("val_iou", 0.0)
     << " % | " << std::setprecision(3) << v.value("val_gradient_mse", 0.0) << loss_note << " | "
     << std::setprecision(1) << v.value("val_gradient_angle_deg", 0.0) << " deg | "
     << std::setprecision(3) << v.value("val_escape_mse", 0.0) << loss_note << " | "
     << std::setprecision(1) << v.value("val_escape_angle_deg", 0.0) << " deg |\n";
}

// Table 3's heading, what its columns mean and its header row.
constexpr const char* kNetworkTableIntro =
    "## The multi-task network (Table 3 layout)\n\n"
    "Validation figures (the epoch with the best validation IoU) on the validation scenes "
    "of the dataset (`data/train_sweethome3d`: 1000 Sweet Home 3D scenes of train-split "
    "chairs and tables, 20 frames each; whole scenes held out for validation: 16,000 "
    "training and 4,000 validation frames), at the network's resolution. The rows from "
    "`doc/training/` were trained by `scripts/train_table3.sh` (their commands in their "
    "manifests there, with logs and curves; every run's IoU per epoch: "
    "[doc/training/iou_per_epoch.png](doc/training/iou_per_epoch.png)): the five variants "
    "under the paper's loss on the same data, at the same resolution, for the same number "
    "of epochs, one thread each, one run each; a name with `_bce<X>` adds X times a "
    "pixel-wise cross-entropy to the loss, a further tag more training scenes (the "
    "manifest lists the datasets; the validation frames are the same). The shipped models: "
    "the commands in `models/MANIFEST.md`. Training = the run's wall time. "
    "Epoch = best / of; a+b: a warm restart, b more epochs (a new cosine schedule) from "
    "weights trained for a epochs (`--init-from`; the minutes of the runs before first). "
    "Dice = soft Dice loss 1 - (2 sum(p t) + 1) / (sum(p^2) + sum(t^2) + 1), mean over "
    "images (Eq. 10); IoU (of the occlusion class, over all validation "
    "pixels) and pixel accuracy of the occlusion map thresholded at 0.5; MSE = "
    "||prediction - (sin, cos)||^2 (Eq. 11; for -L1 rows the SmoothL1 loss, beta 0.01, they "
    "were trained with); angle = mean angular error of the normalised "
    "prediction (gradient: the descent direction of the simulator's gradient; escape: the "
    "oracle's direction of escape).\n\n"
    "The paper's rows: 256 px ShapeNet images (130,000 with its validation split), 50 epochs, "
    "its own gradient labels. Its Dice column is not comparable: the authors' loss "
    "(`loss.py`) is 1 - (sum(p t) + 1) / (sum(p^2) + sum(t^2) + 1), without the factor 2, "
    "so a perfect map scores 0.5 there; its IoU is the same occlusion-class IoU, averaged "
    "over batches of 128.\n\n"
    "| Model | Variant | Size | Epoch | Training | Dice | Pixel acc | IoU | Gradient MSE | "
    "Gradient angle | Escape MSE | Escape angle "
    "|\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";

// The paper's rows of Table 3.
constexpr const char* kPaperNetworkRows =
    "| paper: Base UNet | unet | 256 | - / 50 | - | (0.607) | 99.65 % | 61.09 % | 0.038 | - | - | "
    "- |\n"
    "| paper: R-UNet | r_unet | 256 | - / 50 | - | (0.606) | 99.65 % | 61.47 % | 0.038 | - | - | - "
    "|\n"
    "| paper: SR-UNet | sr_unet | 256 | - / 50 | - | (0.610) | 99.64 % | 60.34 % | 0.038 | - | - | "
    "- |\n"
    "| paper: SAR-UNet | sar_unet | 256 | - / 50 | - | (0.609) | 99.66 % | 61.87 % | 0.038 | - | - "
    "| - |\n"
    "| paper: SAR-UNet-L1 | sar_unet-L1 | 256 | - / 50 | - | (0.604) | 99.67 % | 62.37 % | 0.005 | "
    "- | - | - |\n"
    "\n";

// The trained variants (doc/training/*.json) in the paper's order, each resolution together.
std::vector<nlohmann::json> trainedVariants(const EvalOptions& cl) {
  std::vector<nlohmann::json> runs =
      manifestsIn(fs::path(cl.source_dir) / "doc" / "training", "multitask_unet");
  const auto rank = [](const nlohmann::json& m) {
    const std::string loss =
        m.value("training", nlohmann::json::object()).value("direction_loss", "mse");
    const std::vector<std::string> order = {"unet", "r_unet", "sr_unet", "sar_unet"};
    const std::string variant = m.at("network").value("variant", "");
    const auto at = std::find(order.begin(), order.end(), variant) - order.begin();
    return std::make_pair(m.at("network").value("input_size", 0),
                          2 * static_cast<int>(at) + (loss == "smooth_l1" ? 1 : 0));
  };
  std::stable_sort(runs.begin(), runs.end(), [&](const nlohmann::json& a, const nlohmann::json& b) {
    return rank(a) < rank(b);
  });
  return runs;
}

}  // namespace

std::string networkSection(const EvalOptions& cl) {
  std::ostringstream md;
  md << kNetworkTableIntro;
  for (const nlohmann::json& manifest : trainedVariants(cl)) {
    if (!manifest.contains("network")) continue;
    const std::string file = manifest.value("manifest_file", "?");
    networkRow(md,
               "[" + fs::path(file).stem().string() + "](doc/training/" +
                   fs::path(file).stem().string() + ".png)",
               manifest);
  }
  for (const nlohmann::json& manifest : shippedManifests(cl, "multitask_unet")) {
    if (!manifest.contains("network")) continue;
    networkRow(md, "shipped `" + fs::path(manifest.value("file", "?")).stem().string() + "`",
               manifest);
  }
  md << kPaperNetworkRows;
  return md.str();
}

std::string policySection(const EvalOptions& cl) {
  const std::vector<nlohmann::json> policies = shippedManifests(cl, "ppo_policy");
  if (policies.empty()) return "";
  std::ostringstream md;
  md << "## The PPO policies (Figure 3)\n\n"
     << "The shipped policies (`models/`, trained by `occlusion_train_ppo` on training scenes "
        "and train-split models only; commands and checksums in `models/MANIFEST.md`). Training "
        "end: the means of the last episodes of training (sampled actions, random start "
        "azimuths). Validation: the mean action on 50 validation scenes (Sweet Home 3D chairs "
        "and tables of the train split, seeds 900000-900049, start azimuth 0). Training curves "
        "(the paper's Figure 3): [doc/images/ppo_training.png](doc/images/ppo_training.png), "
        "made by `scripts/plot_ppo.py` from the runs' `training_episodes.csv`.\n\n"
     << "| Policy | Reward | Actor start | Rig inputs | Env steps | Training end: steps | "
        "success | Validation: steps | success |\n|---|---|---|---|---:|---:|---:|---:|---:|\n";
  for (const nlohmann::json& m : policies) {
    const nlohmann::json& t = m.at("trained_with");
    const nlohmann::json& end = m.at("training_end");
    const nlohmann::json& v = m.at("validation");
    md << std::fixed << "| `" << fs::path(m.value("file", "?")).stem().string() << "` | "
       << t.value("reward", "?") << " | "
       << (t.value("actor_from_escape", false) ? "escape head" : "scratch") << " | "
       << (t.at("policy").value("rig_inputs", false) ? "yes" : "no") << " | "
       << m.value("env_steps", 0) << " | " << std::setprecision(1) << end.value("mean_steps", 0.0)
       << " | " << std::setprecision(0) << 100.0 * end.value("success_rate", 0.0) << " % | "
       << std::setprecision(1) << v.value("mean_steps", 0.0) << " +/- " << v.value("std_steps", 0.0)
       << " | " << std::setprecision(0) << 100.0 * v.value("success_rate", 0.0) << " % |\n";
  }
  md << "\n";
  return md.str();
}

}  // namespace report
}  // namespace occlusion_env
