#include "occlusion_env/eval/sweep.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/scene/model_split.hpp"

namespace occlusion_env {
namespace eval {
namespace {

// `text` as one CSV field: in double quotes, inner quotes doubled (RFC 4180).
std::string csvField(const std::string& text) {
  std::string field = "\"";
  for (const char c : text) field += c == '"' ? std::string("\"\"") : std::string(1, c);
  return field + "\"";
}

}  // namespace

std::vector<double> sweepStartAzimuths() {
  const double first = -M_PI / 32.0;
  const double step = M_PI / 208.0;
  // Integer count avoids accumulating the step: (pi/16) / (pi/208) = 13 values.
  const int count = static_cast<int>(std::ceil((M_PI / 16.0) / step - 1e-9));
  std::vector<double> azimuths;
  for (int k = 0; k < count; ++k) azimuths.push_back(first + k * step);
  return azimuths;
}

int defaultSweepModels(const std::string& source) {
  return source == "embedded" ? 1 : 6;
}

std::string sweepSetName(const std::string& preset, const std::string& source) {
  return "sweep_" + preset + (source == "embedded" ? "" : "_" + source);
}

SweepScenes sweepScenes(const std::string& preset, const std::string& source, int models) {
  if (preset != "two_chairs" && preset != "two_tables") {
    throw InvalidArgumentError("sweep preset must be two_chairs or two_tables, got " +
                               quoted(preset));
  }
  if (models < 1) throw InvalidArgumentError("a sweep needs at least one model");
  SweepScenes scenes;
  SceneSet& set = scenes.set;
  set.name = sweepSetName(preset, source);
  set.description = "start-azimuth sweep of the " + preset + " preset";
  set.source = source;
  set.preset = preset;
  set.num_objects = 2;
  set.start_azimuth_rad = 0.0;
  set.start_elevation_rad = 0.0;

  // The evaluation's own environment options, so that a seed draws here what it draws there.
  Environment environment(environmentOptionsFor(set));
  const ObjectCatalog& catalog = environment.library().catalog();
  const std::vector<double> azimuths = sweepStartAzimuths();
  // The model `seed` shows from each start azimuth.
  const auto modelsShown = [&](std::uint64_t seed) {
    ResetOptions reset = resetOptionsFor(set);
    std::vector<ObjectInfo> shown;
    for (const double azimuth : azimuths) {
      reset.start_azimuth_rad = azimuth;
      environment.reset(seed, reset);
      shown.push_back(environment.scene().objects.front().model->info);
    }
    return shown;
  };

  if (models == 1) {
    const std::vector<ObjectInfo> shown = modelsShown(kSweepSeed);
    std::map<std::string, int> counts;  // azimuths per model id
    for (const ObjectInfo& object : shown) ++counts[object.id];
    const ObjectInfo* main = &shown.front();
    for (const ObjectInfo& object : shown) {
      if (counts[object.id] > counts[main->id]) main = &object;
    }
    SweepModel model{kSweepSeed, *main, toString(modelSplitOf(catalog, main->id)), {}};
    for (std::size_t k = 0; k < shown.size(); ++k) {
      if (shown[k].id != main->id) model.redrawn.emplace_back(azimuths[k], shown[k]);
    }
    scenes.models.push_back(model);
    set.seeds.push_back(kSweepSeed);
    return scenes;
  }

  std::set<std::string> seen_ids;
  for (std::uint64_t seed = kSweepSeed;
       seed < kSweepSeed + kSweepSeedSearch && static_cast<int>(scenes.models.size()) < models;
       ++seed) {
    std::set<std::string> ids;
    try {
      for (const ObjectInfo& object : modelsShown(seed)) ids.insert(object.id);
    } catch (const SceneGenerationError&) {
      scenes.skipped.push_back({seed, "no occluded start view from some start azimuth"});
      continue;
    }
    if (ids.size() != 1) {
      scenes.skipped.push_back({seed, "shows " + std::to_string(ids.size()) + " models"});
      continue;
    }
    if (!seen_ids.insert(*ids.begin()).second) {
      scenes.skipped.push_back({seed, "shows " + *ids.begin() + " again"});
      continue;
    }
    const ObjectInfo& object = environment.scene().objects.front().model->info;
    scenes.models.push_back({seed, object, toString(modelSplitOf(catalog, object.id)), {}});
    set.seeds.push_back(seed);
  }
  if (static_cast<int>(scenes.models.size()) < models) {
    throw InvalidArgumentError("only " + std::to_string(scenes.models.size()) + " distinct " +
                               preset + " models among seeds " + std::to_string(kSweepSeed) + ".." +
                               std::to_string(kSweepSeed + kSweepSeedSearch - 1) + " of source " +
                               quoted(source) + ", asked for " + std::to_string(models));
  }
  return scenes;
}

void writeSweepModelsCsv(const std::vector<SweepModel>& models, const std::string& path) {
  std::ofstream csv(path);
  if (!csv) throw InvalidArgumentError("cannot write " + path);
  csv << "seed,id,name,category,split,creator,license,width_m,depth_m,height_m,redrawn\n";
  for (const SweepModel& model : models) {
    const ObjectInfo& object = model.object;
    std::ostringstream redrawn;  // "<start azimuth> deg: <id>; ..."
    for (std::size_t k = 0; k < model.redrawn.size(); ++k) {
      redrawn << (k ? "; " : "") << std::fixed << std::setprecision(2)
              << model.redrawn[k].first * 180.0 / M_PI << " deg: " << model.redrawn[k].second.id;
    }
    csv << model.seed << "," << csvField(object.id) << "," << csvField(object.name) << ","
        << csvField(object.category) << "," << model.split << "," << csvField(object.creator) << ","
        << csvField(object.license) << "," << object.dimensions_m.x() << ","
        << object.dimensions_m.y() << "," << object.dimensions_m.z() << ","
        << csvField(redrawn.str()) << "\n";
  }
}

}  // namespace eval
}  // namespace occlusion_env
