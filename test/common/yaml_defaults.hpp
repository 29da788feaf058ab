// Shipped YAML files state the defaults of an option table: a default changed in the struct and
// not in the file (or the other way round) fails the test that calls expectYamlStatesDefaults.
#pragma once

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

namespace occlusion_env::testing_support {

/// A YAML scalar, sequence or null as the JSON an option table writes for a value like `like`.
inline nlohmann::json yamlAsJson(const YAML::Node& node, const nlohmann::json& like) {
  if (node.IsNull()) return nullptr;
  if (node.IsSequence()) {
    nlohmann::json list = nlohmann::json::array();
    for (std::size_t i = 0; i < node.size(); ++i) {
      list.push_back(yamlAsJson(node[i], like.empty() ? nlohmann::json("") : like[0]));
    }
    return list;
  }
  if (like.is_boolean()) return node.as<bool>();
  if (like.is_number_integer()) return node.as<std::int64_t>();
  if (like.is_number()) return node.as<double>();
  return node.as<std::string>();
}

/// Every key of `defaults` (an OptionTable's toJson of the defaults) is in the YAML file `path`
/// with that value (numbers to 1e-9); with `only_these`, the file has no other keys either.
inline void expectYamlStatesDefaults(const std::string& path, const nlohmann::json& defaults,
                                     bool only_these) {
  const YAML::Node yaml = YAML::LoadFile(path);
  for (const auto& [key, value] : defaults.items()) {
    if (!yaml[key]) {
      ADD_FAILURE() << path << " lacks " << key;
      continue;
    }
    const nlohmann::json stated = yamlAsJson(yaml[key], value);
    if (value.is_number_float() && stated.is_number()) {
      EXPECT_NEAR(stated.get<double>(), value.get<double>(), 1e-9) << path << ": " << key;
    } else {
      EXPECT_EQ(stated, value) << path << ": " << key;
    }
  }
  if (!only_these) return;
  for (const auto& entry : yaml) {
    const std::string key = entry.first.as<std::string>();
    EXPECT_TRUE(defaults.contains(key)) << path << " states " << key << ", which is no option";
  }
}

}  // namespace occlusion_env::testing_support
