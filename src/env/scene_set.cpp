#include "occlusion_env/env/scene_set.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/scene/scene.hpp"

namespace occlusion_env {

namespace {

const std::set<std::string> kKnownKeys = {"name",          "description",   "source",
                                          "catalog_paths", "categories",    "preset",
                                          "num_objects",   "start_azimuth", "start_elevation",
                                          "seeds",         "seed_range",    "model_split"};

std::string listSeeds(const std::vector<std::uint64_t>& seeds) {
  std::ostringstream text;
  const std::size_t shown = std::min<std::size_t>(seeds.size(), 8);
  for (std::size_t i = 0; i < shown; ++i) text << (i > 0 ? ", " : "") << seeds[i];
  if (seeds.size() > shown) text << ", ... (" << seeds.size() << " in all)";
  return text.str();
}

std::vector<std::string> readStrings(const YAML::Node& node) {
  std::vector<std::string> values;
  if (!node) return values;
  for (const auto& item : node) values.push_back(item.as<std::string>());
  return values;
}

}  // namespace

SceneSet loadSceneSet(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& error) {
    throw InvalidArgumentError("scene set " + path + ": " + error.what());
  }
  if (!root.IsMap()) throw InvalidArgumentError("scene set " + path + ": not a YAML map");

  SceneSet set;
  std::string key;
  try {
    for (const auto& entry : root) {
      key = entry.first.as<std::string>();
      if (kKnownKeys.count(key) == 0) throw InvalidArgumentError("unknown key");
    }
    key = "name";
    set.name = root["name"] ? root["name"].as<std::string>() : std::string();
    key = "description";
    if (root["description"]) set.description = root["description"].as<std::string>();
    key = "source";
    if (root["source"]) set.source = root["source"].as<std::string>();
    key = "catalog_paths";
    set.catalog_paths = readStrings(root["catalog_paths"]);
    key = "categories";
    set.categories = readStrings(root["categories"]);
    key = "preset";
    if (root["preset"]) set.preset = root["preset"].as<std::string>();
    parseScenePreset(set.preset);
    key = "model_split";
    if (root["model_split"]) set.model_split = root["model_split"].as<std::string>();
    parseModelSplit(set.model_split);
    key = "num_objects";
    if (root["num_objects"]) set.num_objects = root["num_objects"].as<int>();
    if (set.num_objects < 1) throw InvalidArgumentError("must be >= 1");
    key = "start_azimuth";
    if (root["start_azimuth"]) set.start_azimuth_rad = root["start_azimuth"].as<double>();
    key = "start_elevation";
    if (root["start_elevation"]) set.start_elevation_rad = root["start_elevation"].as<double>();
    key = "seeds";
    if (root["seeds"] && root["seed_range"]) {
      throw InvalidArgumentError("give seeds or seed_range, not both");
    }
    if (root["seeds"]) {
      for (const auto& seed : root["seeds"]) set.seeds.push_back(seed.as<std::uint64_t>());
    } else if (root["seed_range"]) {
      key = "seed_range";
      const auto first = root["seed_range"]["first"].as<std::uint64_t>();
      const auto count = root["seed_range"]["count"].as<std::uint64_t>();
      for (std::uint64_t i = 0; i < count; ++i) set.seeds.push_back(first + i);
    } else {
      throw InvalidArgumentError("missing (give seeds or seed_range)");
    }
    if (set.seeds.empty()) throw InvalidArgumentError("no seeds");
    std::vector<std::uint64_t> sorted = set.seeds;
    std::sort(sorted.begin(), sorted.end());
    const auto duplicate = std::adjacent_find(sorted.begin(), sorted.end());
    if (duplicate != sorted.end()) {
      throw InvalidArgumentError("duplicate seed " + std::to_string(*duplicate));
    }
  } catch (const YAML::Exception& error) {
    throw InvalidArgumentError("scene set " + path + ": key '" + key + "': " + error.what());
  } catch (const std::invalid_argument& error) {
    throw InvalidArgumentError("scene set " + path + ": key '" + key + "': " + error.what());
  }
  if (set.name.empty()) set.name = path;
  return set;
}

void saveSceneSet(const SceneSet& set, const std::string& path) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << set.name;
  out << YAML::Key << "description" << YAML::Value << set.description;
  out << YAML::Key << "source" << YAML::Value << set.source;
  out << YAML::Key << "catalog_paths" << YAML::Value << YAML::Flow << set.catalog_paths;
  out << YAML::Key << "categories" << YAML::Value << YAML::Flow << set.categories;
  out << YAML::Key << "preset" << YAML::Value << set.preset;
  out << YAML::Key << "model_split" << YAML::Value << set.model_split;
  out << YAML::Key << "num_objects" << YAML::Value << set.num_objects;
  out << YAML::Key << "start_azimuth" << YAML::Value << set.start_azimuth_rad;
  out << YAML::Key << "start_elevation" << YAML::Value << set.start_elevation_rad;
  out << YAML::Key << "seeds" << YAML::Value << YAML::Flow << set.seeds;
  out << YAML::EndMap;
  std::ofstream file(path);
  file << out.c_str() << "\n";
  if (!file) throw InvalidArgumentError("cannot write scene set " + path);
}

std::vector<std::uint64_t> sharedSeeds(const SceneSet& first, const SceneSet& second) {
  std::vector<std::uint64_t> a = first.seeds;
  std::vector<std::uint64_t> b = second.seeds;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  std::vector<std::uint64_t> shared;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(shared));
  return shared;
}

std::vector<std::uint64_t> seedsInRange(const SceneSet& set, const SeedRange& range) {
  std::vector<std::uint64_t> inside;
  for (const auto seed : set.seeds) {
    if (range.contains(seed)) inside.push_back(seed);
  }
  std::sort(inside.begin(), inside.end());
  return inside;
}

void requireDisjoint(const SceneSet& first, const SceneSet& second) {
  const auto shared = sharedSeeds(first, second);
  if (!shared.empty()) {
    throw InvalidArgumentError("scene sets '" + first.name + "' and '" + second.name +
                               "' share seeds: " + listSeeds(shared));
  }
}

void requireDisjoint(const SceneSet& set, const SeedRange& range) {
  const auto inside = seedsInRange(set, range);
  if (!inside.empty()) {
    throw InvalidArgumentError(
        "scene set '" + set.name + "' has seeds in [" + std::to_string(range.first) + ", " +
        std::to_string(range.first + range.count) + "): " + listSeeds(inside));
  }
}

EnvironmentOptions environmentOptionsFor(const SceneSet& set, EnvironmentOptions base) {
  base.catalog.source = set.source;
  base.catalog.paths = set.catalog_paths;
  base.scene.categories = set.categories;
  base.scene.num_objects = set.num_objects;
  base.scene.model_split = parseModelSplit(set.model_split);
  base.preset = set.preset;
  return base;
}

ResetOptions resetOptionsFor(const SceneSet& set) {
  ResetOptions reset;
  reset.preset = set.preset;
  reset.categories = set.categories;
  reset.start_azimuth_rad = set.start_azimuth_rad;
  reset.start_elevation_rad = set.start_elevation_rad;
  return reset;
}

}  // namespace occlusion_env
