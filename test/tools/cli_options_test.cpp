// Command lines made from option tables: flags, checks, help text and exit codes.
#include "occlusion_env/tools/cli_options.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "occlusion_env/env/environment.hpp"

namespace occlusion_env::tools {
namespace {

struct ToolArguments {
  std::uint64_t seed = 0;
  bool check = false;
  std::vector<std::string> agents{"random"};
  std::optional<double> azimuth_rad;
  bool augment = true;
  std::vector<std::string> classes{"chair", "table"};
};

const OptionTable<ToolArguments>& toolTable() {
  static const auto table =
      OptionTable<ToolArguments>()
          .add("seed", &ToolArguments::seed, OptionSpec("scene seed"))
          .add("check", &ToolArguments::check, OptionSpec("check only"))
          .add("agents", &ToolArguments::agents, OptionSpec("agents to run"))
          .add("azimuth", &ToolArguments::azimuth_rad, OptionSpec("start azimuth").unit("rad"))
          .add("augment", &ToolArguments::augment,
               OptionSpec("colour jitter").negatedFlag("--no-augment"))
          .add("classes", &ToolArguments::classes,
               OptionSpec("classes to draw").flag("--class").repeatable());
  return table;
}

struct Parsed {
  int exit_code;
  ToolArguments tool;
  EnvironmentOptions environment;
};

Parsed parse(std::vector<std::string> words) {
  Parsed parsed{-1, {}, {}};
  CLI::App app("test tool", "tool_under_test");
  addOptionFlags(app, toolTable(), parsed.tool);
  addOptionFlags(app, environmentOptionTable(), parsed.environment,
                 {"radius", "categories", "catalog_source", "normalize_action"});
  words.insert(words.begin(), "tool_under_test");
  std::vector<const char*> argv;
  for (const std::string& word : words) argv.push_back(word.c_str());
  parsed.exit_code = parseCommandLine(app, static_cast<int>(argv.size()), argv.data());
  return parsed;
}

TEST(CliOptionsTest, FlagsStoreIntoTheirFields) {
  const Parsed parsed =
      parse({"--seed", "18446744073709551615", "--check", "--agents", "a,b", "--azimuth", "-0.5",
             "--radius", "2", "--category", "chair", "--category", "table", "--source",
             "sweethome3d", "--normalize-action", "false"});
  ASSERT_EQ(parsed.exit_code, -1);
  EXPECT_EQ(parsed.tool.seed, 18446744073709551615ULL);
  EXPECT_TRUE(parsed.tool.check);
  EXPECT_EQ(parsed.tool.agents, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(parsed.tool.azimuth_rad, -0.5);
  EXPECT_EQ(parsed.environment.radius_m, 2.0);
  EXPECT_EQ(parsed.environment.scene.categories, (std::vector<std::string>{"chair", "table"}));
  EXPECT_EQ(parsed.environment.catalog.source, "sweethome3d");
  EXPECT_FALSE(parsed.environment.normalize_action);
}

TEST(CliOptionsTest, ANegatedFlagTurnsItsOptionOffAndTakesNoValue) {
  EXPECT_TRUE(parse({}).tool.augment);
  const Parsed parsed = parse({"--no-augment"});
  ASSERT_EQ(parsed.exit_code, -1);
  EXPECT_FALSE(parsed.tool.augment);
  EXPECT_EQ(parse({"--no-augment", "true"}).exit_code, 2);
  EXPECT_EQ(parse({"--augment"}).exit_code, 2);
}

TEST(CliOptionsTest, ARepeatedFlagReplacesTheDefaultList) {
  EXPECT_EQ(parse({}).tool.classes, (std::vector<std::string>{"chair", "table"}));
  EXPECT_EQ(parse({"--class", "sofa"}).tool.classes, (std::vector<std::string>{"sofa"}));
  EXPECT_EQ(parse({"--class", "sofa", "--class", "bed"}).tool.classes,
            (std::vector<std::string>{"sofa", "bed"}));
}

TEST(CliOptionsTest, ParseAndRunGivesTheExitCodes) {
  const auto exitCode = [](std::vector<const char*> argv, const std::function<int()>& run) {
    ToolArguments tool;
    CLI::App app("test tool", "tool_under_test");
    addOptionFlags(app, toolTable(), tool);
    argv.insert(argv.begin(), "tool_under_test");
    return parseAndRun(app, static_cast<int>(argv.size()), argv.data(), run);
  };
  EXPECT_EQ(exitCode({"--seed", "x"}, [] { return 0; }), 2);
  EXPECT_EQ(exitCode({"--help"}, [] { return 1; }), 0);
  EXPECT_EQ(exitCode({}, [] { return 3; }), 3);
  EXPECT_EQ(exitCode({}, []() -> int { throw std::runtime_error("disk full"); }), 1);
}

TEST(CliOptionsTest, DefaultsStayWhenFlagsAreAbsent) {
  const Parsed parsed = parse({});
  ASSERT_EQ(parsed.exit_code, -1);
  EXPECT_EQ(parsed.tool.agents, (std::vector<std::string>{"random"}));
  EXPECT_FALSE(parsed.tool.azimuth_rad.has_value());
  EXPECT_EQ(parsed.environment.radius_m, EnvironmentOptions().radius_m);
}

TEST(CliOptionsTest, MalformedCommandLinesExitWithTwo) {
  EXPECT_EQ(parse({"--seed", "1.5"}).exit_code, 2);
  EXPECT_EQ(parse({"--seed", "-1"}).exit_code, 2);
  EXPECT_EQ(parse({"--radius", "0"}).exit_code, 2);
  EXPECT_EQ(parse({"--radius", "nan"}).exit_code, 2);
  EXPECT_EQ(parse({"--source", "shapenet"}).exit_code, 2);
  EXPECT_EQ(parse({"--agents", "a,,b"}).exit_code, 2);
  EXPECT_EQ(parse({"--check", "maybe"}).exit_code, 2);
  EXPECT_EQ(parse({"--no-such-flag"}).exit_code, 2);
  EXPECT_EQ(parse({"--help"}).exit_code, 0);
}

TEST(CliOptionsTest, HelpShowsMeaningRangeUnitAndDefaultFromTheTable) {
  EnvironmentOptions environment;
  CLI::App app("test tool", "tool_under_test");
  addOptionFlags(app, environmentOptionTable(), environment, {"radius", "catalog_source"});
  const std::string help = app.help();
  EXPECT_NE(help.find("radius of the viewing sphere around the scene centre; > 0 [m] (default 4)"),
            std::string::npos)
      << help;
  EXPECT_NE(help.find("--source"), std::string::npos) << help;
  EXPECT_NE(help.find("embedded | sweethome3d | folder (default embedded)"), std::string::npos)
      << help;
}

}  // namespace
}  // namespace occlusion_env::tools
