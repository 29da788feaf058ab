// The shipped configuration must state the core's defaults: config/sim.yaml is what users read
// to learn them, so a default changed in one place and not the other fails here.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>

#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace {

/// A YAML scalar or sequence as the JSON the option table writes (numbers compared by value).
nlohmann::json asJson(const YAML::Node& node, const nlohmann::json& like) {
  if (node.IsSequence()) {
    nlohmann::json list = nlohmann::json::array();
    for (std::size_t i = 0; i < node.size(); ++i) {
      list.push_back(asJson(node[i], like.empty() ? nlohmann::json("") : like[0]));
    }
    return list;
  }
  if (like.is_boolean()) return node.as<bool>();
  if (like.is_number_integer()) return node.as<std::int64_t>();
  if (like.is_number()) return node.as<double>();
  return node.as<std::string>();
}

TEST(ShippedConfigTest, SimYamlStatesEveryEnvironmentOptionWithItsDefault) {
  const YAML::Node yaml =
      YAML::LoadFile(std::string(OCCLUSION_ENV_SOURCE_DIR) + "/config/sim.yaml");
  const nlohmann::json defaults = environmentOptionTable().toJson(EnvironmentOptions());
  for (const auto& [key, value] : defaults.items()) {
    ASSERT_TRUE(yaml[key]) << "config/sim.yaml lacks " << key;
    const nlohmann::json stated = asJson(yaml[key], value);
    if (value.is_number_float()) {
      EXPECT_NEAR(stated.get<double>(), value.get<double>(), 1e-9) << key;
    } else {
      EXPECT_EQ(stated, value) << key;
    }
  }
}

}  // namespace
}  // namespace occlusion_env
