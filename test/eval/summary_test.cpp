// Episode CSV round trip, Table 4 figures and the Markdown summary.
#include "occlusion_env/eval/summary.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "occlusion_env/core/errors.hpp"

namespace occlusion_env {
namespace eval {
namespace {

std::vector<EpisodeRecord> syntheticRecords() {
  // random: 10..19 steps on scenes 0..9, scene 9 failed (50 steps counted);
  // gradient: 4 fewer steps on every scene, varied by +/- 1.
  std::vector<EpisodeRecord> records;
  for (int scene = 0; scene < 10; ++scene) {
    EpisodeRecord random{"random", "set", 1'000'000u + scene, 0.0, 50, 10 + scene, scene != 9,
                         12.0,     0.5};
    if (scene == 9) random.steps = 50;
    EpisodeRecord gradient = random;
    gradient.agent = "gradient";
    gradient.steps = 6 + scene + (scene % 2 == 0 ? 1 : -1);
    gradient.success = true;
    gradient.final_occlusion_px = 0.0;
    records.push_back(random);
    records.push_back(gradient);
  }
  return records;
}

TEST(EpisodeCsv, RoundTripsEveryField) {
  const auto records = syntheticRecords();
  const auto path = (std::filesystem::temp_directory_path() / "episodes_test.csv").string();
  {
    std::ofstream out(path);
    out << episodeCsvHeader() << "\n";
    for (const auto& record : records) writeEpisodeCsvRow(out, record);
  }
  const auto loaded = readEpisodeCsv(path);
  ASSERT_EQ(loaded.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    EXPECT_EQ(loaded[i].agent, records[i].agent);
    EXPECT_EQ(loaded[i].scene_seed, records[i].scene_seed);
    EXPECT_EQ(loaded[i].steps, records[i].steps);
    EXPECT_EQ(loaded[i].success, records[i].success);
    EXPECT_EQ(loaded[i].max_steps, records[i].max_steps);
    EXPECT_EQ(loaded[i].final_occlusion_px, records[i].final_occlusion_px);
  }
  std::ofstream(path, std::ios::app) << "random,set,1,0,50,x,1,0,0\n";
  EXPECT_THROW(readEpisodeCsv(path), InvalidArgumentError);
  std::remove(path.c_str());

  std::ostringstream sink;
  EpisodeRecord bad = records[0];
  bad.agent = "a,b";
  EXPECT_THROW(writeEpisodeCsvRow(sink, bad), InvalidArgumentError);
}

TEST(Summary, ReadsAgentNodeCsvsAndRefusesCutShortEpisodes) {
  // An agent node's CSV: our nine columns, then completed, message and the camera path.
  const std::string path = ::testing::TempDir() + "/agent_node_episodes.csv";
  const std::string header = episodeCsvHeader() + ",completed,message,azimuths_rad,elevations_rad";
  std::ofstream(path) << header << "\n"
                      << "gradient,ros,7,0,50,2,1,0,0.01,1,,0;0.05;0.1,0;0;0\n";
  const auto loaded = readEpisodeCsv(path);
  ASSERT_EQ(loaded.size(), 1u);
  EXPECT_EQ(loaded[0].agent, "gradient");
  EXPECT_EQ(loaded[0].scene_seed, 7u);
  EXPECT_EQ(loaded[0].steps, 2);
  EXPECT_TRUE(loaded[0].success);

  std::ofstream(path, std::ios::app) << "gradient,ros,8,0,50,3,0,12,0.01,0,lost the simulator: "
                                        "step failed,0;0.05;0.1;0.15,0;0;0;0\n";
  try {
    readEpisodeCsv(path);
    ADD_FAILURE() << "a cut-short episode was accepted";
  } catch (const InvalidArgumentError& error) {
    EXPECT_NE(std::string(error.what()).find(":3:"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("cut short"), std::string::npos) << error.what();
  }
  std::ofstream(path) << episodeCsvHeader() << "X\n";
  EXPECT_THROW(readEpisodeCsv(path), InvalidArgumentError);
  std::remove(path.c_str());
}

TEST(Summary, CountsFailuresWithTheStepLimit) {
  const auto summaries = summarizeAgents(syntheticRecords());
  ASSERT_EQ(summaries.size(), 2u);
  EXPECT_EQ(summaries[0].agent, "random");
  EXPECT_EQ(summaries[0].episodes, 10);
  EXPECT_EQ(summaries[0].successes, 9);
  // 10 + 11 + ... + 18 = 126, plus 50 for the failure.
  EXPECT_DOUBLE_EQ(summaries[0].mean_steps, (126.0 + 50.0) / 10.0);
  EXPECT_EQ(summaries[1].successes, 10);
}

TEST(Summary, MarkdownHasBothTablesWithPaperFigures) {
  const auto records = syntheticRecords();
  BestOptions options;
  options.samples_per_chain = 2000;
  options.burn_in_iterations = 500;
  const auto comparisons = compareAgents(records, options);
  ASSERT_EQ(comparisons.size(), 1u);
  EXPECT_EQ(comparisons[0].first, "random");
  EXPECT_EQ(comparisons[0].second, "gradient");
  EXPECT_EQ(comparisons[0].best.pairs, 10);
  EXPECT_GT(comparisons[0].best.probability_mu_positive, 0.95);  // gradient needs fewer steps
  const std::string md = renderSummaryMarkdown("Test", "", summarizeAgents(records), comparisons);
  EXPECT_NE(md.find("| random (Random) | 10 | 9 | 90.0 % | 1 (50) | 17.6 |"), std::string::npos)
      << md;
  EXPECT_NE(md.find("31.5 | 13.9"), std::string::npos);
  EXPECT_NE(md.find("| random (Random) | gradient (Env. Grad) | 10 |"), std::string::npos) << md;
  EXPECT_NE(md.find("[6.42, 14.97], 10.73, 100.00 %"), std::string::npos);
}

TEST(Summary, IdenticalAgentsGiveNoVariationRow) {
  std::vector<EpisodeRecord> records;
  for (int scene = 0; scene < 5; ++scene) {
    for (const char* agent : {"a", "b"}) {
      records.push_back({agent, "set", 1'000'000u + scene, 0.0, 50, 50, false, 3.0, 0.1});
    }
  }
  const auto comparisons = compareAgents(records);
  ASSERT_EQ(comparisons.size(), 1u);
  EXPECT_TRUE(comparisons[0].best.no_variation);
  const std::string md = renderSummaryMarkdown("T", "", summarizeAgents(records), comparisons);
  EXPECT_NE(md.find("no variation"), std::string::npos) << md;
}

}  // namespace
}  // namespace eval
}  // namespace occlusion_env
