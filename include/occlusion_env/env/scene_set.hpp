// Scene sets: a named list of scene seeds with everything else that fixes a scene (object source,
// categories, preset, object count, start pose), stored as YAML (config/scenes/*.yaml) so that an
// evaluation is reproducible and shareable.
//
// Seed ranges: training uses seeds below kFirstTestSeed, test sets draw theirs from
// [kFirstTestSeed, ...), so that no test scene was ever seen in training. A seed only names the
// same scene under the same source and options, but the disjointness checks compare seeds alone
// (the conservative choice).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {

/// Seeds [first, first + count).
struct SeedRange {
  std::uint64_t first = 0;
  std::uint64_t count = 0;
  bool contains(std::uint64_t seed) const { return seed >= first && seed - first < count; }
};

/// The first seed of the test ranges; training seeds are [0, kFirstTestSeed).
inline constexpr std::uint64_t kFirstTestSeed = 1'000'000;
inline constexpr SeedRange kTrainingSeedRange{0, kFirstTestSeed};
/// Validation scenes (choosing hyper-parameters): the top of the training range, which trainers
/// that draw scene seeds (occlusion_train_ppo) leave out.
inline constexpr std::uint64_t kFirstValidationSeed = 900'000;
/// The seeds trainers draw their scenes from: evaluations refuse them (validation and test
/// scenes are evaluated; validation scenes choose models, test scenes report them).
inline constexpr SeedRange kTrainerSeedRange{0, kFirstValidationSeed};

struct SceneSet {
  std::string name;
  std::string description;
  std::string source = "embedded";         // embedded | sweethome3d | folder
  std::vector<std::string> catalog_paths;  // as CatalogOptions::paths (empty: the default)
  std::vector<std::string> categories;     // empty: any category
  std::string preset = "random";           // random | two_chairs | two_tables
  std::string model_split = "all";         // all | train | test (scene/model_split.hpp)
  int num_objects = 3;
  double start_azimuth_rad = 0.0;  // the paper's comparison starts every episode at 0
  double start_elevation_rad = 0.0;
  std::vector<std::uint64_t> seeds;  // in evaluation order, no duplicates
};

/// Reads a scene set. The file gives either `seeds: [...]` or `seed_range: {first, count}`.
/// Throws InvalidArgumentError naming the file and the bad key (unknown keys included).
SceneSet loadSceneSet(const std::string& path);

/// Writes `set` in the format loadSceneSet reads (seeds as an explicit list).
void saveSceneSet(const SceneSet& set, const std::string& path);

/// Seeds that occur in both sets, ascending.
std::vector<std::uint64_t> sharedSeeds(const SceneSet& first, const SceneSet& second);

/// Seeds of `set` that lie in `range`, ascending.
std::vector<std::uint64_t> seedsInRange(const SceneSet& set, const SeedRange& range);

/// Throws InvalidArgumentError listing (the first few) shared seeds when the sets overlap.
void requireDisjoint(const SceneSet& first, const SceneSet& second);
/// Throws InvalidArgumentError when any seed of `set` lies in `range` (e.g. the training range).
void requireDisjoint(const SceneSet& set, const SeedRange& range);

/// The environment options for the set's scenes: `base` with the set's source, categories,
/// object count and preset.
EnvironmentOptions environmentOptionsFor(const SceneSet& set, EnvironmentOptions base = {});

/// Per-reset overrides fixing the set's start pose.
ResetOptions resetOptionsFor(const SceneSet& set);

}  // namespace occlusion_env
