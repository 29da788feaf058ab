// The paper's start-azimuth sweep (Section 6.2.1, Figure 5): a preset scene (two copies of one
// chair or one table) started from azimuths over [-pi/32, pi/32) in steps of pi/208, on one model
// or on several (one scene seed per model).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/scene/object_catalog.hpp"

namespace occlusion_env {
namespace eval {

/// The first seed tried for the preset's model; outside the training range.
inline constexpr std::uint64_t kSweepSeed = 1'002'000;
inline constexpr int kSweepMaxSteps = 2000;  // the paper's plot limit
/// Seeds tried from kSweepSeed up before giving up on finding enough distinct models.
inline constexpr int kSweepSeedSearch = 200;

/// -pi/32 + k pi/208 for k = 0, 1, ... while below pi/32: 13 azimuths [rad].
std::vector<double> sweepStartAzimuths();

/// Models per sweep when none is asked for: 1 for the embedded source (its one scene, seed
/// kSweepSeed), 6 for the others (Sweet Home 3D: several chairs and tables, not one).
int defaultSweepModels(const std::string& source);

/// "sweep_<preset>" for the embedded source, "sweep_<preset>_<source>" otherwise.
std::string sweepSetName(const std::string& preset, const std::string& source);

/// One scene seed of a sweep and the model (a chair or a table, placed twice) it shows.
struct SweepModel {
  std::uint64_t seed = 0;
  ObjectInfo object;  // the model shown from the most start azimuths (the first of a tie)
  std::string split;  // its split in the catalogue: "train" | "test"
  /// The start azimuths [rad] from which the seed shows another model, with that model: the
  /// environment redraws a scene whose start view is unoccluded. Empty in a sweep of several
  /// models; the one-model sweep keeps kSweepSeed as first published, so it may have some.
  std::vector<std::pair<double, ObjectInfo>> redrawn;
};

/// A seed a sweep of several models tried and left out, and why (e.g. "shows <id> again").
struct SkippedSweepSeed {
  std::uint64_t seed = 0;
  std::string reason;
};

/// A sweep's scenes: the scene set (its seeds in model order) and the model each seed shows.
struct SweepScenes {
  SceneSet set;
  std::vector<SweepModel> models;
  std::vector<SkippedSweepSeed> skipped;
};

/// `models` scenes of `preset` ("two_chairs" | "two_tables", else InvalidArgumentError) from
/// `source` (any source with chair and table categories), elevation 0. One model: the seed
/// kSweepSeed, whatever it shows (the sweep as first published). Several: the seeds from
/// kSweepSeed up, skipping a seed whose model an earlier seed showed or that shows another model
/// from some start azimuth, so that each seed shows one model of its own over the whole sweep;
/// InvalidArgumentError when kSweepSeedSearch seeds give fewer. The set is named by
/// sweepSetName(); the start azimuth is set per episode. Renders each seed tried from every start
/// azimuth (a fraction of a second per seed).
SweepScenes sweepScenes(const std::string& preset, const std::string& source, int models);

/// One row per seed: seed, and its model's id, name, category, split, creator, license, width_m,
/// depth_m, height_m, then redrawn ("<start azimuth> deg: <id>; ..." for the others it shows).
/// Text fields quoted. Throws InvalidArgumentError when `path` cannot be written.
void writeSweepModelsCsv(const std::vector<SweepModel>& models, const std::string& path);

}  // namespace eval
}  // namespace occlusion_env
