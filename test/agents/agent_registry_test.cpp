#include "occlusion_env/agents/agent_registry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <type_traits>
#include <vector>

#include <opencv2/core.hpp>

#include "agents/test_agent.hpp"
#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace {

// An environment that offers nothing but images: what a real camera gives.
class CameraOnlyEnvironment : public EnvironmentInterface {
 public:
  CameraOnlyEnvironment() {
    observation_.rgb = cv::Mat(64, 64, CV_8UC3, cv::Scalar(10, 20, 30));
    observation_.depth = cv::Mat(64, 64, CV_32FC1, cv::Scalar(2.0f));
  }
  StepResult reset(std::uint64_t, const ResetOptions&) override { return result(); }
  StepResult step(const Action& action) override {
    pose_.azimuth_rad += 0.05 * action.d_azimuth_rad;
    return result();
  }
  std::string describe() const override { return "a camera"; }

 private:
  StepResult result() {
    StepResult result;
    result.observation = &observation_;
    result.info.pose = pose_;
    result.info.occlusion.total_pixels = 7;
    return result;
  }
  Observation observation_;
  SphericalPose pose_;
};

TEST(AgentRegistryTest, CoreAgentsAreListedWithWhatTheyNeed) {
  const AgentRegistry registry = coreAgents();
  ASSERT_GE(registry.entries().size(), 2u);
  for (const AgentEntry& entry : registry.entries()) {
    EXPECT_FALSE(entry.summary.empty()) << entry.name;
    EXPECT_TRUE(entry.make) << entry.name;
  }
  // References (the oracle) are listed but do not compete.
  for (const std::string& name : registry.competitors()) EXPECT_TRUE(registry.at(name).competes);
  EXPECT_LT(registry.competitors().size(), registry.names().size());
  EXPECT_EQ(registry.find("test_circling"), nullptr);
  try {
    registry.at("no_such_agent");
    ADD_FAILURE() << "an unknown agent was found";
  } catch (const InvalidArgumentError& error) {
    // The message lists the known agents.
    for (const std::string& name : registry.names()) {
      EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
    }
  }
}

TEST(AgentRegistryTest, RefusesBadEntries) {
  AgentRegistry registry;
  AgentEntry entry = testing_support::circlingAgentEntry();
  registry.add(entry);
  EXPECT_THROW(registry.add(entry), InvalidArgumentError);  // twice
  entry.name = "Has Space";
  EXPECT_THROW(registry.add(entry), InvalidArgumentError);
  entry.name = "a,b";
  EXPECT_THROW(registry.add(entry), InvalidArgumentError);
  entry.name = "no_factory";
  entry.make = nullptr;
  EXPECT_THROW(registry.add(entry), InvalidArgumentError);
}

TEST(AgentRegistryTest, NeedsAreCheckedAgainstTheEnvironment) {
  const AgentRegistry registry = coreAgents();
  CameraOnlyEnvironment camera;
  for (const AgentEntry& entry : registry.entries()) {
    const std::string unmet = registry.unmetNeed(entry.name, camera);
    if (entry.needs.occlusion_gradient || entry.needs.simulation ||
        entry.needs.privileged_observation) {
      EXPECT_FALSE(unmet.empty()) << entry.name;
      EXPECT_THROW(registry.make(entry.name, {camera, ""}), InvalidStateError) << entry.name;
    } else {
      EXPECT_EQ(unmet, "") << entry.name;
      EXPECT_NE(registry.make(entry.name, {camera, ""}), nullptr);
    }
  }
  EXPECT_THROW(camera.occlusionGradient(), InvalidStateError);
  EXPECT_THROW(camera.privilegedObservation(), InvalidStateError);
}

// Detectors of a member by name, to state at compile time what a type does not hold.
#define OCCLUSION_ENV_MEMBER_DETECTOR(NAME) \
  template <typename T, typename = void>    \
  struct Has_##NAME : std::false_type {};   \
  template <typename T>                     \
  struct Has_##NAME<T, std::void_t<decltype(std::declval<T&>().NAME)>> : std::true_type {};
OCCLUSION_ENV_MEMBER_DETECTOR(instance)
OCCLUSION_ENV_MEMBER_DETECTOR(amodal_bits)
OCCLUSION_ENV_MEMBER_DETECTOR(occlusion_mask)
OCCLUSION_ENV_MEMBER_DETECTOR(occlusion)
OCCLUSION_ENV_MEMBER_DETECTOR(environment)
#undef OCCLUSION_ENV_MEMBER_DETECTOR

TEST(AgentRegistryTest, AnAgentIsHandedWhatACameraGivesByType) {
  // act() takes the rig's observation and nothing else.
  static_assert(std::is_same_v<decltype(&Agent::act), Action (Agent::*)(const RigObservation&)>);
  // It holds no masks and no true occlusion (the detectors find them in the privileged record).
  static_assert(!Has_instance<RigObservation>::value && Has_instance<PrivilegedObservation>::value);
  static_assert(!Has_amodal_bits<RigObservation>::value &&
                Has_amodal_bits<PrivilegedObservation>::value);
  static_assert(!Has_occlusion_mask<RigObservation>::value &&
                Has_occlusion_mask<PrivilegedObservation>::value);
  static_assert(!Has_occlusion<RigObservation>::value &&
                Has_occlusion<PrivilegedObservation>::value);
  // A factory is handed capabilities, never the environment (which the caller's context holds).
  static_assert(std::is_same_v<AgentFactory,
                               std::function<std::unique_ptr<Agent>(const AgentCapabilities&)>>);
  static_assert(!Has_environment<AgentCapabilities>::value && Has_environment<AgentContext>::value);
  SUCCEED();
}

// What a factory was handed.
struct Handed {
  bool gradient = false, simulation = false, privileged = false;
};

AgentEntry recordingEntry(const std::string& name, const AgentNeeds& needs, Handed& handed) {
  AgentEntry entry;
  entry.name = name;
  entry.summary = "test-only: records what its factory is handed";
  entry.needs = needs;
  entry.make = [&handed](const AgentCapabilities& capabilities) {
    handed.gradient = static_cast<bool>(capabilities.occlusion_gradient);
    handed.simulation = capabilities.simulation != nullptr;
    handed.privileged = static_cast<bool>(capabilities.privileged_observation);
    return std::make_unique<testing_support::CirclingAgent>();
  };
  return entry;
}

TEST(AgentRegistryTest, AFactoryIsHandedOnlyWhatItsNeedsDeclare) {
  EnvironmentOptions options;
  options.width = options.height = 64;
  Environment environment(options);  // offers everything
  AgentNeeds none, gradient, simulation, privileged;
  gradient.occlusion_gradient = true;
  simulation.simulation = true;
  privileged.privileged_observation = true;
  Handed by_none, by_gradient, by_simulation, by_privileged;
  AgentRegistry registry;
  registry.add(recordingEntry("needs_none", none, by_none));
  registry.add(recordingEntry("needs_gradient", gradient, by_gradient));
  registry.add(recordingEntry("needs_simulation", simulation, by_simulation));
  registry.add(recordingEntry("needs_privileged", privileged, by_privileged));
  for (const std::string& name : registry.names())
    ASSERT_NE(registry.make(name, {environment, ""}), nullptr);
  EXPECT_FALSE(by_none.gradient || by_none.simulation || by_none.privileged);
  EXPECT_TRUE(by_gradient.gradient && !by_gradient.simulation && !by_gradient.privileged);
  EXPECT_TRUE(!by_simulation.gradient && by_simulation.simulation && !by_simulation.privileged);
  EXPECT_TRUE(!by_privileged.gradient && !by_privileged.simulation && by_privileged.privileged);
  // The shipped agents that compete read nothing a camera cannot give.
  const AgentRegistry core = coreAgents();
  for (const std::string& name : core.competitors()) {
    const AgentNeeds& needs = core.at(name).needs;
    EXPECT_FALSE(needs.simulation || needs.privileged_observation) << name;
  }
}

TEST(AgentRegistryTest, RefusesAPrivilegedAgentWhereNoPrivilegedObservationIs) {
  std::vector<testing_support::TruthRead> reads;
  AgentRegistry registry;
  registry.add(testing_support::truthReadingAgentEntry(reads));
  CameraOnlyEnvironment camera;
  const std::string unmet = registry.unmetNeed("test_truth_reading", camera);
  EXPECT_NE(unmet.find("privileged observation"), std::string::npos) << unmet;
  EXPECT_NE(unmet.find("a camera"), std::string::npos) << unmet;  // what does not offer it
  try {
    registry.make("test_truth_reading", {camera, ""});
    ADD_FAILURE() << "a privileged agent was made on a camera";
  } catch (const InvalidStateError& error) {
    EXPECT_EQ(std::string(error.what()), unmet);
  }
}

TEST(AgentRegistryTest, APrivilegedAgentReadsTheTrueMasksOfTheViewItActsOn) {
  std::vector<testing_support::TruthRead> reads;
  AgentRegistry registry;
  registry.add(testing_support::truthReadingAgentEntry(reads));
  EnvironmentOptions options;
  options.width = options.height = 96;
  Environment environment(options);
  EXPECT_THROW(environment.privilegedObservation(), InvalidStateError);  // no view yet
  const std::unique_ptr<Agent> agent = registry.make("test_truth_reading", {environment, ""});
  std::vector<testing_support::TruthRead> truth;  // of each view, as the environment shows it
  EpisodeRunOptions run;
  run.max_steps = 5;
  run.on_result = [&truth](const StepResult& result) {
    const cv::Mat& mask = result.observation->occlusion_mask;
    truth.push_back({result.info.occlusion.total_pixels, cv::countNonZero(mask), mask.data,
                     result.info.step_index});
  };
  EpisodeRequest request;
  request.agent = "test_truth_reading";
  request.scene_set = "unit";
  request.seed = 3;
  const EpisodeRecord record = runEpisode(environment, *agent, request, run);
  ASSERT_TRUE(record.completed()) << record.message;
  ASSERT_EQ(reads.size(), static_cast<std::size_t>(record.steps));  // one read per act
  ASSERT_GT(truth.size(), reads.size());
  EXPECT_GT(truth[0].occlusion_px, 0);  // the start view is occluded
  for (std::size_t t = 0; t < reads.size(); ++t) {
    SCOPED_TRACE("view " + std::to_string(t));
    EXPECT_EQ(reads[t].step_index, truth[t].step_index);
    EXPECT_EQ(reads[t].occlusion_px, truth[t].occlusion_px);
    EXPECT_EQ(reads[t].occlusion_mask_pixels, truth[t].occlusion_mask_pixels);
    EXPECT_EQ(reads[t].mask_data, truth[t].mask_data);  // the environment's buffer, no copy
  }
}

// Records what it is given and checks it against the environment it runs on.
class RigCheckingAgent : public Agent {
 public:
  explicit RigCheckingAgent(const Environment& environment) : environment_(environment) {}
  void reset(std::uint64_t) override { last_ = Action{}; }
  Action act(const RigObservation& observation) override {
    EXPECT_EQ(&observation.rgb, &environment_.observation().rgb);  // the buffers, not a copy
    EXPECT_EQ(&observation.depth, &environment_.observation().depth);
    const CameraIntrinsics& k = environment_.intrinsics();
    EXPECT_EQ(observation.intrinsics.width, observation.rgb.cols);
    EXPECT_EQ(observation.intrinsics.fx, k.fx);
    EXPECT_EQ(observation.intrinsics.cy, k.cy);
    EXPECT_EQ(observation.pose.azimuth_rad, environment_.info().pose.azimuth_rad);
    EXPECT_TRUE(observation.world_from_optical.isApprox(environment_.info().world_from_optical));
    EXPECT_EQ(observation.step_index, acts_);
    EXPECT_EQ(observation.last_action.d_azimuth_rad, last_.d_azimuth_rad);
    EXPECT_EQ(observation.last_action.d_elevation_rad, last_.d_elevation_rad);
    ++acts_;
    last_ = {1.0, 0.25 * acts_};
    return last_;
  }
  int acts() const { return acts_; }

 private:
  const Environment& environment_;
  Action last_;
  int acts_ = 0;
};

TEST(AgentRegistryTest, ARigObservationHoldsTheViewTheIntrinsicsThePoseAndTheLastMove) {
  EnvironmentOptions options;
  options.width = options.height = 96;
  options.camera_randomization.enabled = true;  // intrinsics drawn per scene
  Environment environment(options);
  RigCheckingAgent agent(environment);
  EpisodeRequest request;
  request.agent = "test_rig";
  request.scene_set = "unit";
  request.seed = 5;
  EpisodeRunOptions run;
  run.max_steps = 4;
  const EpisodeRecord record = runEpisode(environment, agent, request, run);
  EXPECT_TRUE(record.completed()) << record.message;
  EXPECT_EQ(agent.acts(), record.steps);
  EXPECT_GT(agent.acts(), 0);
}

TEST(AgentRegistryTest, ATestOnlyAgentRunsInProcessThroughTheRegistry) {
  AgentRegistry registry = coreAgents();
  registry.add(testing_support::circlingAgentEntry());
  EnvironmentOptions options;
  options.width = options.height = 96;
  Environment environment(options);
  const std::unique_ptr<Agent> agent = registry.make("test_circling", {environment, ""});
  EpisodeRequest request;
  request.agent = "test_circling";
  request.scene_set = "unit";
  request.seed = 3;
  request.reset.start_azimuth_rad = 0.0;
  EpisodeRunOptions run;
  run.max_steps = 6;
  const EpisodeRecord record = runEpisode(environment, *agent, request, run);
  EXPECT_TRUE(record.completed()) << record.message;
  ASSERT_EQ(record.path.size(), static_cast<std::size_t>(record.steps) + 1);
  for (int t = 1; t <= record.steps; ++t) {
    EXPECT_NEAR(record.path[t].azimuth_rad - record.path[t - 1].azimuth_rad, 0.05, 1e-12);
    EXPECT_EQ(record.path[t].elevation_rad, 0.0);
  }
}

}  // namespace
}  // namespace occlusion_env
