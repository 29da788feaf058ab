// Table 4 figures and the Markdown summary (the episode CSV is tested in test/agents/).
#include "occlusion_env/eval/summary.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace eval {
namespace {

EpisodeRecord record(const std::string& agent, std::uint64_t seed, int steps, bool success) {
  EpisodeRecord record;
  record.agent = agent;
  record.scene_set = "set";
  record.scene_seed = seed;
  record.max_steps = 50;
  record.steps = steps;
  record.end = success ? EpisodeEnd::kSuccess : EpisodeEnd::kStepLimit;
  record.final_occlusion_px = success ? 0 : 12;
  record.wall_time_s = 0.5;
  return record;
}

std::vector<EpisodeRecord> syntheticRecords() {
  // random: 10..19 steps on scenes 0..9, scene 9 failed (50 steps counted);
  // gradient: 4 fewer steps on every scene, varied by +/- 1.
  std::vector<EpisodeRecord> records;
  for (int scene = 0; scene < 10; ++scene) {
    const std::uint64_t seed = 1'000'000u + scene;
    records.push_back(record("random", seed, scene == 9 ? 50 : 10 + scene, scene != 9));
    records.push_back(record("gradient", seed, 6 + scene + (scene % 2 == 0 ? 1 : -1), true));
  }
  return records;
}

TEST(Summary, RefusesCutShortEpisodes) {
  std::vector<EpisodeRecord> records = syntheticRecords();
  records[3].end = EpisodeEnd::kEnvironmentLost;
  records[3].message = "lost the environment at step 3";
  try {
    summarizeAgents(records, coreAgents());
    ADD_FAILURE() << "a cut-short episode was accepted";
  } catch (const InvalidArgumentError& error) {
    EXPECT_NE(std::string(error.what()).find("cut short"), std::string::npos) << error.what();
  }
}

TEST(Summary, CountsFailuresWithTheStepLimit) {
  const auto summaries = summarizeAgents(syntheticRecords(), coreAgents());
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
  const auto comparisons = compareAgents(records, coreAgents(), options);
  ASSERT_EQ(comparisons.size(), 1u);
  EXPECT_EQ(comparisons[0].first, "random");
  EXPECT_EQ(comparisons[0].second, "gradient");
  EXPECT_EQ(comparisons[0].best.pairs, 10);
  EXPECT_GT(comparisons[0].best.probability_mu_positive, 0.95);  // gradient needs fewer steps
  const std::string md =
      renderSummaryMarkdown("Test", "", summarizeAgents(records, coreAgents()), comparisons);
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
      records.push_back(record(agent, 1'000'000u + scene, 50, false));
    }
  }
  const auto comparisons = compareAgents(records, coreAgents());
  ASSERT_EQ(comparisons.size(), 1u);
  EXPECT_TRUE(comparisons[0].best.no_variation);
  const std::string md =
      renderSummaryMarkdown("T", "", summarizeAgents(records, coreAgents()), comparisons);
  EXPECT_NE(md.find("no variation"), std::string::npos) << md;
}

}  // namespace
}  // namespace eval
}  // namespace occlusion_env
