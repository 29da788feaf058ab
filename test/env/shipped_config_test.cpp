// The shipped configuration must state the core's defaults: config/sim.yaml is what users read
// to learn them, so a default changed in one place and not the other fails here.
#include <gtest/gtest.h>

#include <string>

#include "common/yaml_defaults.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace {

TEST(ShippedConfigTest, SimYamlStatesEveryEnvironmentOptionWithItsDefault) {
  // The simulator node's own options are checked with the ROS layer (ros_unit_tests).
  testing_support::expectYamlStatesDefaults(
      std::string(OCCLUSION_ENV_SOURCE_DIR) + "/config/sim.yaml",
      environmentOptionTable().toJson(EnvironmentOptions()), /*only_these=*/false);
}

}  // namespace
}  // namespace occlusion_env
