// The camera bridge's options without a master: the arrival tolerance scaled to the step, the new
// options' ranges, and launch/camera_bridge.launch's arguments (each documented; those that
// default to the config file name its value correctly).
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "occlusion_env/ros/camera_bridge.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace occlusion_env {
namespace {

TEST(CameraBridgeArrivalTolerance, IsAFractionOfTheStepAtTheWorkingRadius) {
  CameraBridgeOptions options;  // 4 m, 0.05 rad steps (0.2 m), a tenth of a step
  ArrivalTolerance tolerance = arrivalTolerance(options);
  EXPECT_NEAR(tolerance.position_m, 0.02, 1e-12);
  EXPECT_NEAR(tolerance.angle_rad, 0.005, 1e-12);
  // An arm at 0.6 m: the step is 3 cm, the tolerance 3 mm (it was 1 cm, a third of the step).
  options.environment.radius_m = 0.6;
  tolerance = arrivalTolerance(options);
  EXPECT_NEAR(tolerance.position_m, 0.003, 1e-12);
  EXPECT_NEAR(tolerance.angle_rad, 0.005, 1e-12);  // a step turns the view by step_size anyway
  options.arrival_tolerance_steps = 0.5;
  options.environment.step_size_rad = 0.1;
  tolerance = arrivalTolerance(options);
  EXPECT_NEAR(tolerance.position_m, 0.03, 1e-12);
  EXPECT_NEAR(tolerance.angle_rad, 0.05, 1e-12);
}

TEST(CameraBridgeOptionsTest, TheCoresOptionsAreTheNodesByTheSameNames) {
  // The in-process bridge (occlusion_agents --through-bridge) decides as the node does: the
  // node's table holds the core's fields, names, specs and defaults.
  const auto& core = cameraEnvironmentOptionTable();
  const auto& node = cameraBridgeOptionTable();
  const nlohmann::json node_defaults = node.toJson(CameraBridgeOptions());
  const nlohmann::json core_defaults = core.toJson(CameraEnvironmentOptions());
  ASSERT_GE(core.fields().size(), 14u);
  for (const auto& field : core.fields()) {
    const auto* same = node.find(field.key);
    ASSERT_NE(same, nullptr) << field.key << " is not a parameter of the node";
    EXPECT_EQ(same->spec.help(), field.spec.help()) << field.key;
    EXPECT_EQ(node_defaults.at(field.key), core_defaults.at(field.key)) << field.key;
  }
  // A parameter set on the node reaches the core.
  CameraBridgeOptions changed;
  node.set(changed, "confirm_views", 3);
  node.set(changed, "occlusion_threshold", 16);
  node.set(changed, "clear_bounding_surfaces", false);
  EXPECT_FALSE(changed.environment.clear_bounding_surfaces);
  EXPECT_EQ(changed.environment.rule().confirm_views, 3);
  EXPECT_EQ(changed.environment.rule().reward.success_threshold_pixels, 16);
}

TEST(CameraBridgeOptionsTest, SafetyOptionsAreRefusedOutsideTheirRanges) {
  const auto refused = [](auto change, const std::string& name) {
    CameraBridgeOptions options;
    change(options);
    try {
      options.validate();
      ADD_FAILURE() << name << " accepted";
    } catch (const ParameterError& error) {
      EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
    }
  };
  refused([](CameraBridgeOptions& o) { o.arrival_tolerance_steps = 0.0; }, "arrival_tolerance");
  // More than half a step would take a frame nearer the start than the goal.
  refused([](CameraBridgeOptions& o) { o.arrival_tolerance_steps = 0.6; }, "arrival_tolerance");
  refused([](CameraBridgeOptions& o) { o.environment.min_valid_depth_fraction = 0.0; },
          "min_valid_depth_fraction");
  refused([](CameraBridgeOptions& o) { o.environment.min_valid_depth_fraction = 1.5; },
          "min_valid_depth_fraction");
  refused([](CameraBridgeOptions& o) { o.environment.working_range_factor = 0.5; },
          "working_range_factor");
  refused([](CameraBridgeOptions& o) { o.settle_time_s = -0.1; }, "settle_time");
  refused([](CameraBridgeOptions& o) { o.environment.second_occlusion_probability = 1.0; },
          "second_occlusion_probability");
  // A second opinion joins a first one; alone it would silently be the only estimate.
  refused([](CameraBridgeOptions& o) { o.second_model_path = "second.pt"; }, "second_model");
}

struct LaunchArgument {
  std::string default_value, doc;
};

// The <arg> elements of a launch file: name -> default and doc.
std::map<std::string, LaunchArgument> launchArguments(const std::string& path) {
  std::ifstream file(path);
  std::ostringstream text;
  text << file.rdbuf();
  const std::string launch = text.str();
  static const std::regex arg(R"(<arg\b([^>]*?)/>)");
  static const std::regex name(R"(\bname="([^"]*)\")");
  static const std::regex default_value(R"(\bdefault="([^"]*)\")");
  static const std::regex doc(R"(\bdoc="([^"]*)\")");
  std::map<std::string, LaunchArgument> arguments;
  for (std::sregex_iterator it(launch.begin(), launch.end(), arg), end; it != end; ++it) {
    const std::string attributes = (*it)[1].str();
    std::smatch found;
    if (!std::regex_search(attributes, found, name)) continue;
    LaunchArgument& argument = arguments[found[1].str()];
    if (std::regex_search(attributes, found, default_value)) argument.default_value = found[1];
    if (std::regex_search(attributes, found, doc)) argument.doc = found[1];
  }
  return arguments;
}

TEST(CameraBridgeLaunch, ArgumentsForTheRobotSideAreDocumentedWithTheConfigsDefaults) {
  const auto arguments =
      launchArguments(std::string(OCCLUSION_ENV_SOURCE_DIR) + "/launch/camera_bridge.launch");
  ASSERT_GT(arguments.size(), 10u);
  for (const auto& [name, argument] : arguments) {
    EXPECT_FALSE(argument.doc.empty())
        << "camera_bridge.launch: argument " << name << " has no doc";
  }
  for (const std::string name : {"goal_topic", "sphere_frame", "radius", "arrival_timeout",
                                 "frame_timeout", "settle_time", "arrival_tolerance"}) {
    EXPECT_EQ(arguments.count(name), 1u) << "camera_bridge.launch has no argument " << name;
  }
  // An argument left at "config" keeps the config file's value; its doc names the default.
  const nlohmann::json defaults = cameraBridgeOptionTable().toJson(CameraBridgeOptions());
  int from_config = 0;
  for (const auto& [name, argument] : arguments) {
    if (argument.default_value != "config") continue;
    ++from_config;
    ASSERT_TRUE(defaults.contains(name)) << name << " is no option of the bridge";
    std::ostringstream stated;
    stated << "the config file's value (" << defaults[name].get<double>();
    EXPECT_NE(argument.doc.find(stated.str()), std::string::npos)
        << name << ": the doc should say " << stated.str() << "...): " << argument.doc;
  }
  EXPECT_EQ(from_config, 10);
}

}  // namespace
}  // namespace occlusion_env
