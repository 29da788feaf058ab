// runEvaluation with several worker threads (occlusion_eval --threads): the same records, CSV rows
// and truths in the same order as with one, and a failing episode stops the run with its message.
#include <gtest/gtest.h>

#include <atomic>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/eval/evaluation.hpp"

namespace occlusion_env {
namespace eval {
namespace {

EvaluationPlan smallPlan() {
  EvaluationPlan plan;
  plan.scenes.name = "five_scenes";
  plan.scenes.seeds = {11, 12, 13, 14, 15};
  plan.agents = {"random", "gradient"};
  plan.max_steps = 15;
  plan.environment.width = plan.environment.height = 64;
  return plan;
}

// `csv` without its wall_time_s column, the one field that differs from run to run.
std::string withoutWallTime(const std::string& csv) {
  std::istringstream lines(csv);
  std::string out;
  for (std::string line; std::getline(lines, line);) {
    std::size_t start = 0;
    for (int comma = 0; comma < 9; ++comma) start = line.find(',', start) + 1;
    const std::size_t end = line.find(',', start);
    out += line.substr(0, start) + line.substr(end) + "\n";
  }
  return out;
}

// Everything runEvaluation hands back: the records, the CSV it wrote (wall time aside) and the
// truths through the bridge.
struct RunOutput {
  std::vector<EpisodeRecord> records;
  std::string csv;
  std::vector<std::int64_t> truth;
};

RunOutput run(const EvaluationPlan& plan) {
  RunOutput output;
  std::ostringstream csv;
  output.records = runEvaluation(plan, coreAgents(), &csv, nullptr, &output.truth);
  output.csv = withoutWallTime(csv.str());
  return output;
}

constexpr int kLimitPx = 290;  // see ClearWhenSmall

// Says a view is clear when the objects fill fewer than `limit_px` of its pixels: an estimate that
// changes from view to view, so that the episodes through the bridge differ in length.
class ClearWhenSmall : public ViewOcclusionEstimator {
 public:
  explicit ClearWhenSmall(int limit_px) : limit_px_(limit_px) {}
  std::int64_t estimate(const cv::Mat& rgb, const cv::Mat& depth, const CameraIntrinsics&,
                        cv::Mat& mask) override {
    mask = cv::Mat::zeros(rgb.size(), CV_8UC1);
    const int filled_px = cv::countNonZero(depth > 0);  // no return (NaN) is not > 0
    return filled_px < limit_px_ ? 0 : filled_px;
  }

 private:
  int limit_px_;
};

TEST(EvaluationThreads, GiveTheSameRecordsInTheSameOrderAsOne) {
  EvaluationPlan plan = smallPlan();
  const RunOutput one = run(plan);
  ASSERT_EQ(one.records.size(), 10u);
  plan.threads = 3;
  const RunOutput three = run(plan);
  EXPECT_EQ(three.csv, one.csv);  // every field but the wall time, in the same order
  ASSERT_EQ(three.records.size(), one.records.size());
  for (std::size_t i = 0; i < one.records.size(); ++i) {
    EXPECT_EQ(three.records[i].agent, one.records[i].agent);
    EXPECT_EQ(three.records[i].scene_seed, one.records[i].scene_seed);
    EXPECT_EQ(three.records[i].steps, one.records[i].steps);
  }
  EXPECT_TRUE(one.truth.empty());  // not through the bridge
  EXPECT_TRUE(three.truth.empty());
  // More threads than episodes: as many as there are episodes.
  plan.scenes.seeds = {11};
  plan.agents = {"gradient"};
  plan.threads = 8;
  std::istringstream lines(one.csv);
  std::vector<std::string> rows;
  for (std::string line; std::getline(lines, line);) rows.push_back(line + "\n");
  ASSERT_EQ(rows.size(), 11u);                      // the header and 10 episodes
  EXPECT_EQ(run(plan).csv, rows[0] + rows[1 + 5]);  // gradient's first, after random's 5
}

TEST(EvaluationThreads, ThroughTheBridgeEachWorkerHasItsOwnEstimatorAndTheTruthsKeepTheirOrder) {
  EvaluationPlan plan = smallPlan();
  plan.agents = {"random"};
  plan.bridge.confirm_views = 1;
  plan.bridge.min_valid_depth_fraction = 0.001;  // 64 px of the void: the objects fill little
  std::atomic<int> made{0};
  plan.bridge_estimators = [&made] {
    ++made;
    return std::make_unique<ClearWhenSmall>(kLimitPx);
  };
  const RunOutput one = run(plan);
  plan.threads = 2;
  const RunOutput two = run(plan);
  EXPECT_EQ(two.csv, one.csv);
  EXPECT_EQ(two.truth, one.truth);
  ASSERT_EQ(two.truth.size(), 5u);
  EXPECT_EQ(made, 1 + 2);  // one estimator per worker
  std::set<int> steps;
  for (const EpisodeRecord& record : one.records) steps.insert(record.countedSteps());
  EXPECT_GT(steps.size(), 1u) << "every episode as long: the order is not tested";
}

TEST(EvaluationThreads, AFailingEpisodeStopsTheRunWithItsMessage) {
  AgentRegistry registry = coreAgents();
  AgentEntry failing;
  failing.name = "fails_on_13";
  failing.summary = "a random walk that refuses scene 13";
  failing.make = [](const AgentCapabilities&) {
    class FailsOn13 : public Agent {
     public:
      void reset(std::uint64_t seed) override { seed_ = seed; }
      Action act(const RigObservation&) override {
        if (seed_ == 13) throw std::runtime_error("scene 13 refused");
        return Action{1.0, 0.0};
      }

     private:
      std::uint64_t seed_ = 0;
    };
    return std::make_unique<FailsOn13>();
  };
  registry.add(failing);
  EvaluationPlan plan = smallPlan();
  plan.agents = {"fails_on_13"};
  plan.threads = 2;
  try {
    runEvaluation(plan, registry, nullptr, nullptr);
    FAIL() << "the run went on past a failed episode";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("fails_on_13 on scene 13"), std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("scene 13 refused"), std::string::npos)
        << error.what();
  }
  plan.threads = 0;
  EXPECT_THROW(runEvaluation(plan, registry, nullptr, nullptr), InvalidArgumentError);
}

}  // namespace
}  // namespace eval
}  // namespace occlusion_env
