// DAgger (Ross, Gordon & Bagnell 2011): imitation on the agent's own states. The current
// predicted-escape agent (learning/learned_agents.hpp) is rolled out on training scenes; every
// state it visits is labelled with the oracle's answer (escape direction, steps; lattice spacing
// 0.5 steps) and written as a dataset in occlusion_dataset's format (dataset/scene_writer.hpp),
// which `occlusion_train --data BASE --data DAGGER1 ... --init-from MODEL` trains on.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/dataset/generator.hpp"

namespace occlusion_env {
namespace learning {

struct DaggerOptions {
  std::string model;                  // the agent's network (.pt beside its .json)
  int scenes = 100;                   // roll-outs, one per scene
  std::uint64_t first_seed = 100000;  // scene seeds first_seed .. + scenes - 1 (< 900,000)
  /// Per step, the probability that the oracle's first step is executed instead of the agent's
  /// move (the DAgger mixture); 0: the agent's own states only.
  double beta = 0.0;
  int max_steps = 50;  // a roll-out ends at an unoccluded view or after max_steps moves
  /// Moves of the agent recorded after the first unoccluded view (outside the episode, which has
  /// ended there): the barely clear views a camera's stopping rule must confirm
  /// (doc/TRAINING.md). Within max_steps moves in all.
  int moves_past_clear = 0;
  int threads = 2;  // workers, one environment (GL context) and network each
  /// The scenes' environment and the data's format: size, catalogue, categories, objects,
  /// validation fraction (0 here: the DAgger frames only add training frames). Its scenes,
  /// first_seed, frames and threads are set from the fields above.
  dataset::DatasetOptions data = defaultData();

  /// Throws InvalidArgumentError naming the first bad option; seeds at or above the validation
  /// seeds (900,000: validation, 1,000,000: test) are refused.
  void validate() const;
  /// `data` with the fields above filled in.
  dataset::DatasetOptions datasetOptions() const;
  /// What a resumed run must match: the data's defining options, the model (its canonical path
  /// and a hash of its file), beta and max_steps.
  nlohmann::json definingJson() const;

  static dataset::DatasetOptions defaultData();
};

/// The declared options of DaggerOptions but `data` (whose flags are occlusion_dataset's).
const OptionTable<DaggerOptions>& daggerOptionTable();

struct DaggerReport {
  int scenes_written = 0;
  int scenes_skipped = 0;        // complete already (resume)
  int frames_written = 0;        // labelled states
  int expert_moves = 0;          // steps where the mixture executed the oracle's move
  int successes = 0;             // roll-outs that reached an unoccluded view
  double seconds = 0.0;          // wall clock
  double rollout_seconds = 0.0;  // summed over workers: agent, environment, mixture's oracle
  double write_seconds = 0.0;    // summed over workers: re-render, labels, PNG and JSON
  double oracle_seconds = 0.0;   // summed over workers: the labels' oracle queries (in write)
};

/// Called after each scene with (scenes done in this run, scenes to do, frames written so far).
using DaggerProgress = std::function<void(int done, int total, int frames)>;

/// Writes (or completes) the DAgger dataset in `dir`: per scene a roll-out of the agent from the
/// scene's start view (image 0), one frame per state it visits, the last one included. A folder
/// holding a dataset made with other defining options (or none) is refused (InvalidArgumentError
/// naming them); complete scenes are kept.
DaggerReport writeDaggerDataset(const std::string& dir, const DaggerOptions& options,
                                const DaggerProgress& progress = {});

}  // namespace learning
}  // namespace occlusion_env
