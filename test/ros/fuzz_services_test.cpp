// Hostile input: the reset and step services and the move topic get random and extreme values
// (NaN, +/-inf, 1e308, subnormals, extreme seeds, empty and very long strings, unknown ids,
// out-of-range enums, random catalogue entries). Every request must get either a valid result
// or an error status (never INTERNAL_ERROR, never a dropped call), and the node must still
// serve afterwards.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "occlusion_env/CameraMove.h"
#include "occlusion_env/Reset.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/StepOutcome.h"
#include "occlusion_env/common/random.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/scene/object_catalog.hpp"

namespace occlusion_env {
namespace {

constexpr int kSize = 128;        // the .test file's width and height [px]
constexpr int kIterations = 400;  // requests of each kind

const double kInf = std::numeric_limits<double>::infinity();
const double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Extreme and ordinary numbers, drawn with equal weight.
double hostileNumber(RandomSource& random) {
  static const double kValues[] = {kNaN, kInf, -kInf, 1e308, -1e308, 4.9e-324, -1e-320,
                                   0.0,  -0.0, 1.0,   -1.0,  1e-3,   3.14159,  100.0};
  constexpr std::size_t kCount = sizeof(kValues) / sizeof(kValues[0]);
  const std::uint64_t pick = random.below(kCount + 1);
  return pick < kCount ? kValues[pick] : random.uniform(-10.0, 10.0);
}

std::string hostileString(RandomSource& random, const std::vector<std::string>& valid) {
  switch (random.below(7)) {
    case 0:
      return "";
    case 1:
      return std::string(100000, 'x');
    case 2:
      return "../../../../etc/passwd";
    case 3:
      return std::string("nul\0byte", 8);
    case 4:
      return "two_chairs";
    case 5:
      return valid[random.below(valid.size())];
    default:
      return "\xff\xfe not utf-8 \x01";
  }
}

std::uint64_t hostileSeed(RandomSource& random) {
  static const std::uint64_t kSeeds[] = {0, 1, std::numeric_limits<std::uint64_t>::max(),
                                         std::uint64_t{1} << 63,
                                         static_cast<std::uint64_t>(-1234567)};
  const std::uint64_t pick = random.below(6);
  return pick < 5 ? kSeeds[pick] : random.nextU64();
}

/// An OK response must carry a well-formed observation.
void expectWellFormed(const CameraObservation& observation) {
  EXPECT_EQ(observation.rgb.width, static_cast<unsigned>(kSize));
  EXPECT_EQ(observation.rgb.data.size(), static_cast<std::size_t>(kSize * kSize * 3));
  EXPECT_EQ(observation.depth.data.size(), static_cast<std::size_t>(kSize * kSize * 4));
  EXPECT_TRUE(std::isfinite(observation.azimuth));
  EXPECT_TRUE(std::isfinite(observation.elevation));
  EXPECT_GE(observation.occlusion.total_pixels, 0);
}

void expectHandled(const Status& status, const std::string& what) {
  EXPECT_LT(status.code, Status::INTERNAL_ERROR) << what << ": " << status.message;
  if (status.code != Status::OK) EXPECT_FALSE(status.message.empty()) << what;
  EXPECT_LE(status.message.size(), 2000u) << what;
}

std::vector<std::string> embeddedIds() {
  const auto catalog = makeEmbeddedCatalog();  // held: objects() refers into it
  std::vector<std::string> ids;
  for (const ObjectInfo& info : catalog->objects()) ids.push_back(info.id);
  return ids;
}

TEST(FuzzServices, EveryHostileRequestGetsAResultOrAnErrorStatus) {
  ros::NodeHandle node(names::kNamespace);
  const std::string reset_name = node.resolveName(names::kResetService);
  const std::string step_name = node.resolveName(names::kStepService);
  ASSERT_TRUE(ros::service::waitForService(reset_name, ros::Duration(20.0)));
  ASSERT_TRUE(ros::service::waitForService(step_name, ros::Duration(20.0)));
  ros::ServiceClient reset_client = node.serviceClient<Reset>(reset_name, /*persistent=*/true);
  ros::ServiceClient step_client = node.serviceClient<Step>(step_name, /*persistent=*/true);
  const std::vector<std::string> ids = embeddedIds();
  RandomSource random(2026);

  int ok_resets = 0, ok_steps = 0;
  for (int i = 0; i < kIterations; ++i) {
    Reset reset;
    reset.request.seed = hostileSeed(random);
    if (random.below(2)) reset.request.preset = hostileString(random, ids);
    for (std::uint64_t k = random.below(4); k > 0; --k) {
      reset.request.object_ids.push_back(hostileString(random, ids));
    }
    if (random.below(3) == 0) reset.request.categories.push_back(hostileString(random, ids));
    reset.request.set_start_azimuth = random.below(2);
    reset.request.start_azimuth = hostileNumber(random);
    reset.request.set_start_elevation = random.below(2);
    reset.request.start_elevation = hostileNumber(random);
    ASSERT_TRUE(reset_client.call(reset)) << "reset call " << i << " dropped";
    expectHandled(reset.response.status, "reset " + std::to_string(i));
    if (reset.response.status.code == Status::OK) {
      ++ok_resets;
      expectWellFormed(reset.response.observation);
    }

    for (int s = 0; s < 3; ++s) {
      Step step;
      step.request.action.d_azimuth = hostileNumber(random);
      step.request.action.d_elevation = hostileNumber(random);
      ASSERT_TRUE(step_client.call(step)) << "step call " << i << " dropped";
      expectHandled(step.response.status, "step " + std::to_string(i));
      if (step.response.status.code == Status::OK) {
        ++ok_steps;
        expectWellFormed(step.response.observation);
        EXPECT_TRUE(std::isfinite(step.response.reward));
      }
    }
  }
  // The mix must exercise both outcomes, or the test proves nothing.
  EXPECT_GT(ok_resets, kIterations / 20);
  EXPECT_GT(ok_steps, kIterations / 20);
  RecordProperty("ok_resets", ok_resets);
  RecordProperty("ok_steps", ok_steps);
}

TEST(FuzzServices, HostileMovesGetAnOutcomeAndTheNodeStillServes) {
  ros::NodeHandle node(names::kNamespace);
  int outcomes = 0, internal_errors = 0;
  ros::Subscriber outcome_subscriber = node.subscribe<StepOutcome>(
      names::kStepOutcomeTopic, 1000, [&](const StepOutcome::ConstPtr& outcome) {
        ++outcomes;
        if (outcome->status.code >= Status::INTERNAL_ERROR) ++internal_errors;
      });
  ros::Publisher move_publisher = node.advertise<CameraMove>(names::kMoveTopic, 1000);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while ((move_publisher.getNumSubscribers() == 0 || outcome_subscriber.getNumPublishers() == 0) &&
         ros::WallTime::now() < deadline) {
    ros::WallDuration(0.05).sleep();
  }
  Reset reset;
  reset.request.seed = 3;
  ASSERT_TRUE(ros::service::call(node.resolveName(names::kResetService), reset));
  ASSERT_EQ(reset.response.status.code, Status::OK);

  RandomSource random(7);
  constexpr int kMoves = 200;
  for (int i = 0; i < kMoves; ++i) {
    CameraMove move;
    move.d_azimuth = hostileNumber(random);
    move.d_elevation = hostileNumber(random);
    move_publisher.publish(move);
    ros::WallDuration(0.002).sleep();
  }
  const ros::WallTime wait_until = ros::WallTime::now() + ros::WallDuration(20.0);
  while (outcomes < kMoves && ros::WallTime::now() < wait_until) ros::WallDuration(0.05).sleep();
  EXPECT_EQ(outcomes, kMoves);
  EXPECT_EQ(internal_errors, 0);

  // Still serving, and a plain reset and step still work.
  reset.request.seed = 7;
  ASSERT_TRUE(ros::service::call(node.resolveName(names::kResetService), reset));
  EXPECT_EQ(reset.response.status.code, Status::OK);
  Step step;
  step.request.action.d_azimuth = 1.0;
  ASSERT_TRUE(ros::service::call(node.resolveName(names::kStepService), step));
  EXPECT_EQ(step.response.status.code, Status::OK);
}

}  // namespace
}  // namespace occlusion_env

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "fuzz_services_test");
  ros::AsyncSpinner spinner(1);  // subscription callbacks; the tests run on this thread
  spinner.start();
  return RUN_ALL_TESTS();
}
