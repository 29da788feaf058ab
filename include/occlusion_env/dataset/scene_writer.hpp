// The generator's scene writer for other ways of choosing a scene's frames than Algorithm 1's
// random walk, e.g. the states an agent visits (learning/dagger.hpp): the same files, labels and
// manifest as occlusion_dataset's (dataset/bop_dataset.hpp), so the trainer reads both alike.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "occlusion_env/agents/oracle.hpp"
#include "occlusion_env/dataset/generator.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace dataset {

/// One writer thread's environment, label makers and buffers. The environment's GL context is
/// made on the constructing thread, which must then make every call.
class SceneWriter {
 public:
  SceneWriter(const EnvironmentOptions& options, std::shared_ptr<ObjectLibrary> library);
  ~SceneWriter();
  SceneWriter(const SceneWriter&) = delete;
  SceneWriter& operator=(const SceneWriter&) = delete;

  Environment& environment();
  /// The labels' oracle (lattice spacing 0.5 steps). writeScene() clears it and anchors it at
  /// the scene's start view, so a query made after a reset to the same scene and
  /// oracle().clear(start pose) gives the label's answer.
  OcclusionOracle& oracle();
  /// Writes scene folder `index` of `dir` from scene `seed`: image k at poses[k], with every
  /// label (the oracle's when options.oracle_labels), scene_labels.json last. Resets the
  /// environment to the scene. Throws InvalidArgumentError for no poses, std::runtime_error
  /// naming the file when a write fails.
  void writeScene(const std::string& dir, int index, std::uint64_t seed,
                  const std::vector<SphericalPose>& poses, const DatasetOptions& options);
  /// Seconds spent in the labels' oracle queries so far.
  double oracleSeconds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The environment a dataset made with `options` shows its scenes in.
EnvironmentOptions environmentOptionsFor(const DatasetOptions& options);

/// The manifest generateDataset() writes for `options` (tool, format, options, model split, the
/// scenes with their seeds and train/val split).
nlohmann::json datasetManifest(const DatasetOptions& options, const ObjectCatalog& catalog);

/// Throws InvalidArgumentError unless `dir` is new, empty or holds a dataset whose manifest's
/// "options" equal `defining` (naming each that differs); an option missing there counts as its
/// value in `defaults`. Such a dataset is then resumed.
void requireResumable(const std::string& dir, const nlohmann::json& defining,
                      const nlohmann::json& defaults = nlohmann::json::object());

/// Writes `json` to `path` through a temporary name: a file that exists is complete. Throws
/// std::runtime_error naming the file and the space left when the write fails.
void writeJsonAtomically(const std::string& path, const nlohmann::json& json);

}  // namespace dataset
}  // namespace occlusion_env
