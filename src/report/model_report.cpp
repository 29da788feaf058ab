#include "occlusion_env/report/model_report.hpp"

#include <algorithm>
#include <cmath>
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

// The Epoch cell, "best / of": a warm restart (--init-from) continues the epochs of the run it
// started from, written a+b.
std::string epochCell(const nlohmann::json& manifest) {
  const nlohmann::json training = manifest.value("training", nlohmann::json::object());
  const nlohmann::json start = manifest.value("initialised_from", nlohmann::json::object());
  const std::string before =
      start.contains("epoch")
          ? std::to_string(start.value("epochs_before", start.value("epoch", 0))) + "+"
          : "";
  return before + std::to_string(manifest.value("epoch", 0)) + " / " + before +
         std::to_string(training.value("epochs", 0));
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
  md << epochCell(manifest) << " | ";
  // A warm restart (--init-from) continues the minutes of the run it started from too.
  const nlohmann::json start = manifest.value("initialised_from", nlohmann::json::object());
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
    "manifest lists the datasets; the validation frames are the same). Training = the "
    "run's wall time. "
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

// A figure of a head, or "-" where the model's validation data had no labels for it (the
// trainer then writes 0 for both its loss and its angle).
std::string headFigures(const nlohmann::json& validation, const std::string& head) {
  const double mse = validation.value("val_" + head + "_mse", 0.0);
  const double angle = validation.value("val_" + head + "_angle_deg", 0.0);
  if (mse == 0.0 && angle == 0.0) return "-";
  std::ostringstream out;
  out << std::fixed << std::setprecision(1) << angle << " deg";
  return out.str();
}

// What a shipped network does differently from learning::NetworkConfig's defaults beyond its
// variant and size: its width and input options (doc/TRAINING.md), the field of view in degrees;
// "-" for none. (The report keeps libtorch's headers out; a test holds these to NetworkConfig.)
std::string inputOptions(const nlohmann::json& network) {
  static const nlohmann::json defaults = {
      {"variant", nullptr},          {"input_size", nullptr},   {"levels", nullptr},
      {"base_channels", 8},          {"depth_gaps", "far"},     {"bounding_surfaces", "kept"},
      {"depth_reference", "metres"}, {"escape_bins", 0},        {"view_crop", 1.0},
      {"view_field_of_view", 0.0},   {"depth_validity", "none"}};
  std::ostringstream out;
  for (const auto& [key, value] : network.items()) {
    if (defaults.contains(key) && (defaults[key].is_null() || defaults[key] == value)) continue;
    if (out.tellp() > 0) out << ", ";
    out << key << " ";
    if (key == "view_field_of_view" && value.is_number()) {
      out << std::fixed << std::setprecision(0) << value.get<double>() * 180.0 / M_PI << " deg";
    } else if (value.is_string()) {
      out << value.get<std::string>();
    } else {
      out << value.dump();
    }
  }
  return out.tellp() > 0 ? out.str() : "-";
}

// Where a shipped network's figures were measured: a derived copy (scripts/derive_model.py)
// carries its origin's, else the validation frames of its own datasets.
std::string validationData(const nlohmann::json& manifest) {
  const nlohmann::json derived = manifest.value("derived_from", nlohmann::json::object());
  if (derived.contains("file")) {
    return "those of `" + fs::path(derived.value("file", "?")).stem().string() +
           "` (the same weights)";
  }
  std::ostringstream out;
  if (manifest.contains("validation_frames")) {
    out << manifest.value("validation_frames", 0) << " frames of ";
  }
  out << "`" << manifest.value("dataset", "?") << "`";
  const nlohmann::json extra = manifest.value("extra_datasets", nlohmann::json::array());
  if (extra.size() == 1) {
    out << " and `" << extra[0].get<std::string>() << "`";
  } else if (extra.size() > 1) {
    out << " and " << extra.size() << " more sets";
  }
  return out.str();
}

// One row of the shipped networks' table.
void shippedNetworkRow(std::ostringstream& md, const nlohmann::json& manifest) {
  const nlohmann::json& v = manifest["validation"];
  const nlohmann::json& net = manifest["network"];
  const nlohmann::json training = manifest.value("training", nlohmann::json::object());
  md << std::fixed << "| `" << fs::path(manifest.value("file", "?")).stem().string() << "` | "
     << net.value("variant", "?") << (training.value("bce_weight", 0.0) > 0.0 ? " +BCE" : "")
     << " | " << net.value("input_size", 0) << " | " << inputOptions(net) << " | "
     << epochCell(manifest) << " | " << validationData(manifest) << " | " << std::setprecision(2)
     << 100.0 * v.value("val_iou", 0.0) << " % | " << headFigures(v, "gradient") << " | "
     << headFigures(v, "escape") << " |\n";
}

// The shipped networks' table: each validated on its own data, so not comparable with the rows
// above nor with one another.
constexpr const char* kShippedTableIntro =
    "### The shipped networks\n\n"
    "The networks in `models/` (what each is for: [models/README.md](models/README.md); the "
    "command and checksum of each: `models/MANIFEST.md`). Each was validated on the validation "
    "frames of the data it was trained on, at its own resolution and input, so its figures "
    "compare with neither the table above nor one another: the robustness section below and "
    "`occlusion_train --check` measure networks on the same frames. Input: the options of "
    "its network input beyond RGB-D (doc/TRAINING.md); a copy made by "
    "`scripts/derive_model.py` keeps its origin's weights and figures. Epoch as above; IoU of "
    "the occlusion class; angle = mean angular error of the direction heads (\"-\": no such "
    "labels in its data).\n\n"
    "| Model | Variant | Size | Input | Epoch | Validation frames | IoU | Gradient angle | "
    "Escape angle |\n|---|---|---:|---|---:|---|---:|---:|---:|\n";

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

// What a policy's heads see of the rig: "yes" (the last move and the elevation), the moves they
// remember when more than the last (PolicyConfig::move_memory), or "no".
std::string rigInputsCell(const nlohmann::json& policy) {
  if (!policy.value("rig_inputs", false)) return "no";
  const int moves = policy.value("move_memory", 1);
  return moves == 1 ? "yes" : "yes, the last " + std::to_string(moves) + " moves";
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
  md << kPaperNetworkRows << kShippedTableIntro;
  for (const nlohmann::json& manifest : shippedManifests(cl, "multitask_unet")) {
    if (manifest.contains("network")) shippedNetworkRow(md, manifest);
  }
  md << "\n";
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
       << rigInputsCell(t.at("policy")) << " | " << m.value("env_steps", 0) << " | "
       << std::setprecision(1) << end.value("mean_steps", 0.0) << " | " << std::setprecision(0)
       << 100.0 * end.value("success_rate", 0.0) << " % | " << std::setprecision(1)
       << v.value("mean_steps", 0.0) << " +/- " << v.value("std_steps", 0.0) << " | "
       << std::setprecision(0) << 100.0 * v.value("success_rate", 0.0) << " % |\n";
  }
  md << "\n";
  return md.str();
}

}  // namespace report
}  // namespace occlusion_env
