// A simulator killed in the middle of an agent's episode and started again
// (test/ros/simulator_restart.test). This test owns the simulator process: it starts it, kills it
// with SIGKILL (a crash, no clean shutdown) just after the agent reports its first episode, and
// starts it again a moment later.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <atomic>
#include <string>

#include "agent_test_support.hpp"
#include "occlusion_env/EpisodeReport.h"

extern char** environ;

namespace occlusion_env {
namespace {

// Starts `rosrun occlusion_env occlusion_sim` (rosrun execs it, so the pid is the node's).
pid_t startSimulator() {
  const char* argv[] = {"rosrun", "occlusion_env", "occlusion_sim", nullptr};
  pid_t pid = 0;
  const int error =
      posix_spawnp(&pid, "rosrun", nullptr, nullptr, const_cast<char**>(argv), environ);
  EXPECT_EQ(error, 0) << "cannot start the simulator";
  return error == 0 ? pid : -1;
}

void stopSimulator(pid_t pid, int signal) {
  if (pid <= 0) return;
  kill(pid, signal);
  int status = 0;
  waitpid(pid, &status, 0);
}

TEST(SimulatorRestart, AgentReportsTheLostEpisodeWaitsAndCarriesOn) {
  ros::NodeHandle private_node("~");
  std::string csv;
  int episodes = 0;
  double start_azimuth = 0.0;
  ASSERT_TRUE(private_node.getParam("csv", csv));
  ASSERT_TRUE(private_node.getParam("episodes", episodes));
  private_node.getParam("start_azimuth", start_azimuth);

  std::atomic<int> reports{0};
  ros::NodeHandle node;
  ros::Subscriber report_subscriber = node.subscribe<EpisodeReport>(
      "/random_agent/episodes", 100, [&](const EpisodeReport::ConstPtr&) { ++reports; });
  ros::AsyncSpinner spinner(1);
  spinner.start();

  pid_t simulator = startSimulator();
  ASSERT_GT(simulator, 0);
  // The agent steps at ~step_rate (the .test file): 0.3 s after its first report it is a few
  // steps into its second episode, whose seed takes 50 steps in process.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(60.0);
  while (reports == 0 && ros::WallTime::now() < deadline) ros::WallDuration(0.001).sleep();
  ASSERT_GT(reports, 0) << "the agent reported no episode within 60 s";
  ros::WallDuration(0.3).sleep();
  const int reports_at_kill = reports;
  stopSimulator(simulator, SIGKILL);
  ros::WallDuration(1.5).sleep();  // the agent notices, reports and waits
  simulator = startSimulator();

  const std::vector<EpisodeRecord> rows = testing_support::waitForRows(csv, episodes, 90.0);
  stopSimulator(simulator, SIGINT);
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(episodes)) << csv;
  const ros::WallTime report_deadline = ros::WallTime::now() + ros::WallDuration(5.0);
  while (reports < episodes && ros::WallTime::now() < report_deadline) {
    ros::WallDuration(0.01).sleep();
  }
  EXPECT_EQ(reports, episodes) << "every episode, the cut-short one included, is published";

  int cut_short = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const EpisodeRecord& row = rows[i];
    SCOPED_TRACE("episode " + std::to_string(i) + " seed " + std::to_string(row.scene_seed));
    if (!row.completed()) {
      ++cut_short;
      EXPECT_EQ(static_cast<int>(i), reports_at_kill) << "the episode in flight at the kill";
      EXPECT_EQ(row.end, EpisodeEnd::kEnvironmentLost) << row.message;
      EXPECT_GT(row.steps, 0) << "killed in the middle of the episode, not at its reset";
      continue;
    }
    // Episodes before and after the restart are those of a simulator that never died.
    testing_support::expectSameAsInProcess(row, start_azimuth);
  }
  EXPECT_EQ(cut_short, 1) << "exactly the episode in flight at the kill is cut short";
}

}  // namespace
}  // namespace occlusion_env

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "simulator_restart_test");
  return RUN_ALL_TESTS();
}
