// The option table: one declaration gives JSON in and out, checks and the docs' table.
#include "occlusion_env/common/option_table.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

namespace occlusion_env {
namespace {

struct Inner {
  int count = 3;
};

struct Sample {
  double radius_m = 4.0;
  bool fast = false;
  std::string mode = "a";
  std::vector<std::string> names;
  std::vector<std::uint64_t> seeds{1, 2};
  std::optional<double> azimuth_rad;
  std::size_t budget = 5000;
  Inner inner;
};

const OptionTable<Sample>& sampleTable() {
  static const auto table =
      OptionTable<Sample>()
          .add("radius", &Sample::radius_m, OptionSpec("sphere radius").unit("m").above(0))
          .add("fast", &Sample::fast, OptionSpec("go fast"))
          .add("mode", &Sample::mode, OptionSpec("the mode").choices({"a", "b"}))
          .add("names", &Sample::names, OptionSpec("names").repeatable())
          .add("seeds", &Sample::seeds, OptionSpec("seeds").atLeast(1))
          .add("azimuth", &Sample::azimuth_rad, OptionSpec("start azimuth").unit("rad"))
          .add("budget", &Sample::budget, OptionSpec("triangles").atLeast(0).flag("--lod"))
          .add(
              "count", [](Sample& s) -> int& { return s.inner.count; },
              OptionSpec("objects").range(1, 8));
  return table;
}

std::string errorOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const InvalidArgumentError& error) {
    return error.what();
  }
  return "";
}

TEST(OptionTableTest, JsonRoundTripKeepsEveryField) {
  Sample sample;
  sample.radius_m = 1.5;
  sample.fast = true;
  sample.mode = "b";
  sample.names = {"x", "y"};
  sample.azimuth_rad = 0.25;
  sample.inner.count = 7;
  const nlohmann::json json = sampleTable().toJson(sample);
  EXPECT_EQ(json["count"], 7);
  EXPECT_EQ(json["azimuth"], 0.25);
  Sample copy;
  sampleTable().applyJson(json, copy);
  EXPECT_EQ(sampleTable().toJson(copy), json);
  EXPECT_TRUE(sampleTable().toJson(Sample())["azimuth"].is_null());  // unset optional
}

TEST(OptionTableTest, RefusesUnknownNamesWrongKindsAndOutOfRangeValuesNamingTheOption) {
  Sample sample;
  EXPECT_NE(errorOf([&] {
              sampleTable().applyJson({{"radius", 2.0}, {"nope", 1}}, sample);
            }).find("'nope'"),
            std::string::npos);
  EXPECT_EQ(sample.radius_m, 4.0) << "nothing is stored when one value is refused";
  const std::string range = errorOf([&] { sampleTable().set(sample, "radius", 0.0); });
  EXPECT_EQ(range, "radius must be in > 0 [m], got 0");
  EXPECT_NE(errorOf([&] { sampleTable().set(sample, "count", 9); }).find("count must be in [1, 8]"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { sampleTable().set(sample, "count", 2.5); }).find("an integer"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { sampleTable().set(sample, "mode", "c"); }).find("a | b"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { sampleTable().set(sample, "fast", 1); }).find("true or false"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              sampleTable().set(sample, "seeds", nlohmann::json{3, 0});
            }).find("seeds (each item)"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { sampleTable().set(sample, "budget", -1); }).find("budget"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { sampleTable().set(sample, "radius", "4"); }).find("a finite number"),
            std::string::npos);
}

TEST(OptionTableTest, AcceptsIntegralDoublesForIntegersAsYamlAndXmlRpcSendThem) {
  Sample sample;
  sampleTable().set(sample, "count", 5.0);
  EXPECT_EQ(sample.inner.count, 5);
  sampleTable().set(sample, "radius", 2);  // an integer for a number
  EXPECT_EQ(sample.radius_m, 2.0);
}

TEST(OptionTableTest, CheckFindsAnOutOfRangeValueSetInCode) {
  Sample sample;
  EXPECT_NO_THROW(sampleTable().check(sample));
  sample.inner.count = 0;
  EXPECT_NE(errorOf([&] { sampleTable().check(sample); }).find("count"), std::string::npos);
}

TEST(OptionTableTest, IncludeLiftsAnotherTablesFields) {
  struct Outer {
    Inner inner;
    bool verbose = false;
  };
  const auto inner_table =
      OptionTable<Inner>().add("count", &Inner::count, OptionSpec("objects").range(1, 8));
  auto table = OptionTable<Outer>()
                   .include(inner_table, [](Outer& o) -> Inner& { return o.inner; })
                   .add("verbose", &Outer::verbose, OptionSpec("talk"));
  Outer outer;
  table.applyJson({{"count", 4}, {"verbose", true}}, outer);
  EXPECT_EQ(outer.inner.count, 4);
  EXPECT_TRUE(outer.verbose);
  EXPECT_EQ(table.keys(), (std::vector<std::string>{"count", "verbose"}));
}

TEST(OptionTableTest, MarkdownShowsNameDefaultRangeUnitAndMeaning) {
  const std::string markdown = sampleTable().markdown();
  EXPECT_NE(markdown.find("| `radius` | 4 | > 0 | m | sphere radius |"), std::string::npos)
      << markdown;
  EXPECT_NE(markdown.find("| `mode` | a | a / b |  | the mode |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("| `azimuth` | unset |"), std::string::npos) << markdown;
}

TEST(OptionTableTest, FlagNamesAreDashedKeysUnlessDeclared) {
  EXPECT_EQ(sampleTable().find("radius")->flagName(), "--radius");
  EXPECT_EQ(sampleTable().find("budget")->flagName(), "--lod");
}

}  // namespace
}  // namespace occlusion_env
