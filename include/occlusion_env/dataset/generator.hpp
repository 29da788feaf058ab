// Algorithm 1 of the paper: training frames from random scenes, each scene from a training seed
// at its start view, each next frame after a random camera move, written in the BOP format
// (dataset/bop_dataset.hpp) with occlusion, gradient and oracle labels; and the audit that
// re-renders stored frames and compares.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "occlusion_env/agents/oracle.hpp"
#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace dataset {

struct DatasetOptions {
  int scenes = 1000;                // N_s
  int frames = 20;                  // N_i per scene (the paper's 20)
  std::uint64_t first_seed = 0;     // scene seeds first_seed .. first_seed + scenes - 1 (training)
  int size = 128;                   // image width and height [px]
  std::string source = "embedded";  // object catalogue
  std::vector<std::string> catalog_paths;  // as the simulator's ~catalog_paths
  std::vector<std::string> categories;     // empty: any
  int num_objects = 3;
  /// Between frames the camera takes 1..max_move_steps steps (uniform) of the environment's step
  /// size in one direction drawn uniformly from [0, 2 pi): a random walk of varying stride.
  int max_move_steps = 4;
  /// Frame 0's elevation [rad], drawn per scene from its seed, uniformly in [min, max]; the walk
  /// goes on from there. The scene is drawn at its start view (elevation 0, where it holds
  /// occlusion) as ever, so the same scenes are seen from higher up. 0, 0: the start view itself.
  double first_elevation_min_rad = 0.0;
  double first_elevation_max_rad = 0.0;
  /// Draws of a seed's scene until its start view shows occlusion (EnvironmentOptions'); a seed
  /// that needs more stops the run, naming it.
  int max_scene_attempts = EnvironmentOptions{}.max_scene_attempts;
  bool oracle_labels = true;
  /// Around the targets and what the camera reports (the environment's `world` and
  /// `depth_sensor`, `random` included); unset: void and ideal, or random with `randomize`.
  std::optional<std::string> world;
  std::optional<std::string> depth_sensor;
  /// Draw per scene, from its seed: the camera (radius, field of view, resolution, intrinsics;
  /// env/scene_setup.hpp) and, where not given, the world and the sensor. The frames are what the
  /// sensor gives; the labels (masks, occlusion, gradient, oracle) stay the truth.
  bool randomize = false;
  /// With `randomize`: the ranges the camera is drawn from (env/scene_setup.hpp's defaults;
  /// `enabled` is not used, `randomize` is). Recorded in the manifest as camera_randomization.
  CameraRandomization camera_ranges;
  double validation_fraction = 0.2;  // whole scenes: every 1/fraction-th scene
  int threads = 2;                   // workers, one environment (GL context) each

  /// The options that define the data (not how it is made): what a resumed run must match. The
  /// table's names but scenes and threads (and world, depth_sensor, randomize while unset or
  /// false: a default set's options are as before they existed), with the model split, the
  /// step size and, with randomize, the camera ranges.
  nlohmann::json definingJson() const;
  /// Throws InvalidArgumentError naming the first bad option; test seeds (>= 1,000,000),
  /// anything but the train model split, and camera ranges without `randomize` are refused here.
  void validate() const;
};

/// The declared options of DatasetOptions, by their manifest names; the flags are
/// occlusion_dataset's.
const OptionTable<DatasetOptions>& datasetOptionTable();

struct GenerationReport {
  int scenes_written = 0;
  int scenes_skipped = 0;  // complete already (resume)
  int frames_written = 0;
  double seconds = 0.0;
};

/// Called after each scene with (scenes done in this run, scenes to do in this run).
using ProgressCallback = std::function<void(int done, int total)>;

/// Writes (or completes) the dataset in `dir`. A folder holding a dataset made with other
/// defining options is refused (InvalidArgumentError naming the differing options); complete
/// scenes are kept. Throws std::runtime_error naming the file when a write fails (a full disk).
GenerationReport generateDataset(const std::string& dir, const DatasetOptions& options,
                                 const ProgressCallback& progress = {});

struct AuditReport {
  int frames_checked = 0;
  int failures = 0;
  std::vector<std::string> problems;  // one line per mismatch (at most 50 kept)
};

/// Re-renders `samples` frames drawn (with `seed`) from the dataset in `dir` from their recorded
/// scene seed and pose and compares images (exactly; depth to its quantisation), masks, occlusion,
/// gradient and oracle labels.
AuditReport auditDataset(const std::string& dir, int samples, std::uint64_t seed = 1);

}  // namespace dataset
}  // namespace occlusion_env
