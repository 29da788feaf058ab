// runEvaluation through the camera bridge's logic in front of the simulator (occlusion_eval
// --scenes ... --through-bridge): the records hold the bridge's verdict on its estimate, and the
// simulator's truth where each episode ended comes back beside them.
#include <gtest/gtest.h>

#include <vector>

#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/eval/evaluation.hpp"

namespace occlusion_env {
namespace eval {
namespace {

// An estimator that says the same of every view.
class FixedEstimate : public ViewOcclusionEstimator {
 public:
  std::int64_t estimate(const cv::Mat& rgb, const cv::Mat& /*depth*/, const CameraIntrinsics&,
                        cv::Mat& mask) override {
    mask = cv::Mat::zeros(rgb.size(), CV_8UC1);
    return next_px;
  }
  std::int64_t next_px = 0;
};

TEST(EvaluationThroughTheBridge, RecordsTheBridgesVerdictAndTheTruthWhereEpisodesEnded) {
  EvaluationPlan plan;
  plan.scenes.name = "two_scenes";
  plan.scenes.seeds = {1, 2};
  plan.agents = {"random"};
  plan.max_steps = 12;
  plan.environment.width = plan.environment.height = 64;
  plan.bridge.confirm_views = 1;
  plan.bridge.min_valid_depth_fraction = 0.001;  // 64 px of the void: the objects fill little
  // An estimate that is always clear: the first step ends each episode, whatever the truth.
  std::int64_t estimated_px = 0;
  plan.bridge_estimators = [&estimated_px] {
    auto estimator = std::make_unique<FixedEstimate>();
    estimator->next_px = estimated_px;
    return estimator;
  };
  std::vector<std::int64_t> truth;
  const std::vector<EpisodeRecord> records =
      runEvaluation(plan, coreAgents(), nullptr, nullptr, &truth);
  ASSERT_EQ(records.size(), 2u);
  ASSERT_EQ(truth.size(), 2u);
  for (std::size_t i = 0; i < records.size(); ++i) {
    EXPECT_TRUE(records[i].success());  // the bridge's verdict
    EXPECT_EQ(records[i].steps, 1);
    EXPECT_EQ(records[i].final_occlusion_px, 0);  // its estimate
    EXPECT_EQ(records[i].occlusion_source, OcclusionSource::kEstimated);
    EXPECT_GE(truth[i], 0);  // the simulator's count where it ended
  }
  // An estimate that is never clear: no verdict, the step limit ends each episode.
  estimated_px = 100;
  truth.clear();
  for (const EpisodeRecord& record : runEvaluation(plan, coreAgents(), nullptr, nullptr, &truth)) {
    EXPECT_FALSE(record.success());
    EXPECT_EQ(record.steps, 12);
  }
  EXPECT_EQ(truth.size(), 2u);
  // Views with too little valid depth: each episode fails where it stands (here at its reset)
  // and the evaluation goes on to the next scene.
  plan.bridge.min_valid_depth_fraction = 0.99;
  truth.clear();
  const std::vector<EpisodeRecord> unusable =
      runEvaluation(plan, coreAgents(), nullptr, nullptr, &truth);
  ASSERT_EQ(unusable.size(), 2u);
  for (const EpisodeRecord& record : unusable) {
    EXPECT_EQ(record.end, EpisodeEnd::kUnusableView) << record.message;
    EXPECT_EQ(record.countedSteps(), 12);
    EXPECT_NE(record.message.find("at reset could not be used"), std::string::npos)
        << record.message;
  }
  EXPECT_EQ(truth.size(), 2u);
  plan.bridge.min_valid_depth_fraction = 0.001;
  // Directly on the simulator nothing is written there.
  plan.bridge_estimators = nullptr;
  truth.clear();
  runEvaluation(plan, coreAgents(), nullptr, nullptr, &truth);
  EXPECT_TRUE(truth.empty());
}

}  // namespace
}  // namespace eval
}  // namespace occlusion_env
