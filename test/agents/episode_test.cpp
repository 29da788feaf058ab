#include "occlusion_env/agents/episode.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "agents/test_agent.hpp"
#include "common/temporary_dir.hpp"
#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

EpisodeRecord sampleRecord() {
  EpisodeRecord record;
  record.agent = "random";
  record.scene_set = "test_embedded";
  record.scene_seed = 1000007;
  record.start_azimuth_rad = -0.09817477042468103;
  record.max_steps = 50;
  record.steps = 2;
  record.end = EpisodeEnd::kSuccess;
  record.final_occlusion_px = 0;
  record.wall_time_s = 0.125;
  record.path = {{-0.09817477042468103, 0.0}, {-0.05, 0.1 / 3.0}, {0.0, 1e-17}};
  return record;
}

// Episode CSVs written and read in a scratch folder of their own.
class EpisodeCsvTest : public TemporaryDirTest {};

TEST_F(EpisodeCsvTest, CsvRoundTripKeepsEveryField) {
  EpisodeRecord cut = sampleRecord();
  cut.end = EpisodeEnd::kEnvironmentLost;
  cut.message = "lost, with \"quotes\"\nand a line break";
  cut.final_occlusion_px = -1;
  const std::string path = (dir_ / "episodes.csv").string();
  {
    std::ofstream out(path);
    out << episodeCsvHeader() << '\n';
    writeEpisodeCsvRow(out, sampleRecord());
    writeEpisodeCsvRow(out, cut);
  }
  const std::vector<EpisodeRecord> read = readEpisodeCsv(path);
  ASSERT_EQ(read.size(), 2u);
  const EpisodeRecord& first = read[0];
  const EpisodeRecord expected = sampleRecord();
  EXPECT_EQ(first.agent, expected.agent);
  EXPECT_EQ(first.scene_set, expected.scene_set);
  EXPECT_EQ(first.scene_seed, expected.scene_seed);
  EXPECT_EQ(first.start_azimuth_rad, expected.start_azimuth_rad);  // 17 digits: exact
  EXPECT_EQ(first.end, EpisodeEnd::kSuccess);
  EXPECT_EQ(first.steps, 2);
  ASSERT_EQ(first.path.size(), 3u);
  for (std::size_t t = 0; t < 3; ++t) {
    EXPECT_EQ(first.path[t].azimuth_rad, expected.path[t].azimuth_rad);
    EXPECT_EQ(first.path[t].elevation_rad, expected.path[t].elevation_rad);
  }
  EXPECT_EQ(read[1].end, EpisodeEnd::kEnvironmentLost);
  EXPECT_FALSE(read[1].completed());
  EXPECT_EQ(read[1].final_occlusion_px, -1);
  EXPECT_EQ(read[1].message.find_first_of(",\"\n"), std::string::npos) << read[1].message;
}

TEST_F(EpisodeCsvTest, ReadsVersionOneAndRefusesMalformedFiles) {
  const std::string path = (dir_ / "episodes_v1.csv").string();
  std::ofstream(path) << "agent,scene_set,scene_seed,start_azimuth_rad,max_steps,steps,success,"
                         "final_occlusion_px,wall_time_s\nrandom,s,5,0,50,50,0,223,0.07\n"
                         "gradient,s,5,0,50,12,1,0,0.02\n";
  const std::vector<EpisodeRecord> read = readEpisodeCsv(path);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].end, EpisodeEnd::kStepLimit);
  EXPECT_EQ(read[0].countedSteps(), 50);
  EXPECT_EQ(read[1].end, EpisodeEnd::kSuccess);
  EXPECT_EQ(read[1].countedSteps(), 12);

  const std::string bad_rows[] = {
      "3,random,s,5,0,50,50,0,223,0.07,step_limit,,0,0",    // version 3
      "2,random,s,5,0,50,50,1,223,0.07,step_limit,,0,0",    // success contradicts end
      "2,random,s,5,0,50,50,0,223,0.07,sideways,,0,0",      // unknown end
      "2,random,s,-5,0,50,50,0,223,0.07,step_limit,,0,0",   // negative seed
      "2,random,s,5,0,50,50,0,223,0.07,step_limit,,0;1,0",  // path lengths differ
      "2,random,s,5,0,50,50,0,223,0.07,step_limit,,0",      // a column short
  };
  for (const std::string& row : bad_rows) {
    std::ofstream(path) << episodeCsvHeader() << '\n' << row << '\n';
    EXPECT_THROW(readEpisodeCsv(path), InvalidArgumentError) << row;
  }
  std::ofstream(path) << "something,else\n";
  EXPECT_THROW(readEpisodeCsv(path), InvalidArgumentError);
  std::remove(path.c_str());
  EXPECT_THROW(readEpisodeCsv(path), InvalidArgumentError);  // missing file
  std::ostringstream out;
  EpisodeRecord unnamed = sampleRecord();
  unnamed.agent = "a,b";
  EXPECT_THROW(writeEpisodeCsvRow(out, unnamed), InvalidArgumentError);
}

TEST(EpisodeTest, StatisticsCountFailuresAtTheLimitAndSkipCutShortEpisodes) {
  std::vector<EpisodeRecord> records(4, sampleRecord());
  records[0].steps = 10;
  records[1].steps = 20;
  records[2].end = EpisodeEnd::kStepLimit;  // counted as 50
  records[2].steps = 50;
  records[3].end = EpisodeEnd::kAgentFailed;  // left out
  const EpisodeStatistics stats = summarizeEpisodes(records);
  EXPECT_EQ(stats.episodes, 4);
  EXPECT_EQ(stats.completed, 3);
  EXPECT_EQ(stats.successes, 2);
  EXPECT_DOUBLE_EQ(stats.mean_steps, 80.0 / 3.0);
  EXPECT_NEAR(stats.sd_steps,
              std::sqrt(((10 - 80.0 / 3) * (10 - 80.0 / 3) + (20 - 80.0 / 3) * (20 - 80.0 / 3) +
                         (50 - 80.0 / 3) * (50 - 80.0 / 3)) /
                        2.0),
              1e-12);
  EXPECT_TRUE(std::isnan(summarizeEpisodes({records[0]}).sd_steps));
  EXPECT_TRUE(std::isnan(summarizeEpisodes({}).mean_steps));
  for (EpisodeEnd end :
       {EpisodeEnd::kSuccess, EpisodeEnd::kTruncated, EpisodeEnd::kStepLimit,
        EpisodeEnd::kEnvironmentError, EpisodeEnd::kEnvironmentLost, EpisodeEnd::kAgentFailed,
        EpisodeEnd::kStopped, EpisodeEnd::kUnusableView}) {
    EXPECT_EQ(parseEpisodeEnd(toString(end)), end);
  }
}

// A scripted environment: fails in the way it is told at step `fail_at`.
class ScriptedEnvironment : public EnvironmentInterface {
 public:
  enum class Failure { kNone, kLost, kRefused, kBadObservation, kUnusableView };
  Failure failure = Failure::kNone;
  int fail_at = 3;
  int succeed_at = -1;

  StepResult reset(std::uint64_t, const ResetOptions&) override {
    step_ = 0;
    observation_.rgb = cv::Mat(8, 8, CV_8UC3, cv::Scalar(1, 2, 3));
    observation_.depth = cv::Mat(8, 8, CV_32FC1, cv::Scalar(1.0f));
    return result();
  }
  StepResult step(const Action&) override {
    if (step_ + 1 == fail_at) {
      if (failure == Failure::kLost) throw EnvironmentUnavailableError("the node died");
      if (failure == Failure::kRefused) throw InvalidStateError("episode over");
      if (failure == Failure::kUnusableView) throw UnusableViewError("no valid depth");
      if (failure == Failure::kBadObservation) observation_.rgb.release();
    }
    ++step_;
    StepResult out = result();
    out.terminated = step_ == succeed_at;
    return out;
  }
  std::string describe() const override { return "a script"; }

 private:
  StepResult result() {
    StepResult out;
    out.observation = &observation_;
    out.info.step_index = step_;
    out.info.pose.azimuth_rad = 0.05 * step_;
    out.info.occlusion.total_pixels = 100 - step_;
    return out;
  }
  Observation observation_;
  int step_ = 0;
};

EpisodeRecord runScripted(ScriptedEnvironment& environment, EpisodeRunOptions options = {}) {
  testing_support::CirclingAgent agent;
  EpisodeRequest request;
  request.agent = "test_circling";
  request.scene_set = "script";
  request.seed = 11;
  if (options.max_steps == 50) options.max_steps = 10;
  return runEpisode(environment, agent, request, options);
}

TEST(EpisodeRunnerTest, EveryWayAnEpisodeEndsIsRecorded) {
  ScriptedEnvironment environment;
  EpisodeRecord record = runScripted(environment);
  EXPECT_EQ(record.end, EpisodeEnd::kStepLimit);
  EXPECT_EQ(record.steps, 10);
  EXPECT_EQ(record.final_occlusion_px, 90);
  EXPECT_EQ(record.path.size(), 11u);

  environment.succeed_at = 4;
  record = runScripted(environment);
  EXPECT_EQ(record.end, EpisodeEnd::kSuccess);
  EXPECT_EQ(record.steps, 4);
  environment.succeed_at = -1;

  environment.failure = ScriptedEnvironment::Failure::kLost;
  record = runScripted(environment);
  EXPECT_EQ(record.end, EpisodeEnd::kEnvironmentLost);
  EXPECT_EQ(record.steps, 2);
  EXPECT_NE(record.message.find("the node died"), std::string::npos) << record.message;

  // A camera view that cannot be used ends the episode as a failure the statistics count.
  environment.failure = ScriptedEnvironment::Failure::kUnusableView;
  record = runScripted(environment);
  EXPECT_EQ(record.end, EpisodeEnd::kUnusableView);
  EXPECT_TRUE(record.completed());
  EXPECT_FALSE(record.success());
  EXPECT_EQ(record.countedSteps(), 10);
  EXPECT_NE(record.message.find("step 3 could not be used: no valid depth"), std::string::npos)
      << record.message;

  environment.failure = ScriptedEnvironment::Failure::kRefused;
  record = runScripted(environment);
  EXPECT_EQ(record.end, EpisodeEnd::kEnvironmentError);
  EXPECT_NE(record.message.find("step 3"), std::string::npos) << record.message;

  // An observation the agent cannot act on cuts the episode short; nothing is thrown.
  environment.failure = ScriptedEnvironment::Failure::kBadObservation;
  record = runScripted(environment);
  EXPECT_EQ(record.end, EpisodeEnd::kAgentFailed);
  EXPECT_EQ(record.steps, 3);
  EXPECT_NE(record.message.find("no RGB-D image"), std::string::npos) << record.message;
  environment.failure = ScriptedEnvironment::Failure::kNone;

  int asked = 0;
  EpisodeRunOptions options;
  options.keep_running = [&asked] { return ++asked <= 2; };
  int results = 0;
  options.on_result = [&results](const StepResult&) { ++results; };
  record = runScripted(environment, options);
  EXPECT_EQ(record.end, EpisodeEnd::kStopped);
  EXPECT_EQ(record.steps, 2);
  EXPECT_EQ(results, 3);  // the reset and two steps
}

TEST(EpisodeRunnerTest, StepRateIsHonoured) {
  ScriptedEnvironment environment;
  EpisodeRunOptions options;
  options.max_steps = 5;
  options.step_rate_hz = 100.0;
  const EpisodeRecord record = runScripted(environment, options);
  EXPECT_EQ(record.steps, 5);
  EXPECT_GE(record.wall_time_s, 0.039);  // 4 waits of 10 ms after the first step
  options.step_rate_hz = -1.0;
  EXPECT_THROW(runScripted(environment, options), InvalidArgumentError);
}

}  // namespace
}  // namespace occlusion_env
