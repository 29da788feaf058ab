// The sweep's start azimuths and the progress bar's text.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/eval/progress.hpp"
#include "occlusion_env/eval/sweep.hpp"

namespace occlusion_env {
namespace eval {
namespace {

TEST(Sweep, AzimuthsCoverHalfOpenRangeInPaperSteps) {
  const auto azimuths = sweepStartAzimuths();
  ASSERT_EQ(azimuths.size(), 13u);
  EXPECT_DOUBLE_EQ(azimuths.front(), -M_PI / 32.0);
  EXPECT_LT(azimuths.back(), M_PI / 32.0);
  for (std::size_t i = 1; i < azimuths.size(); ++i) {
    EXPECT_NEAR(azimuths[i] - azimuths[i - 1], M_PI / 208.0, 1e-12);
  }
  const SceneSet chairs = sweepSceneSet("two_chairs");
  EXPECT_EQ(chairs.name, "sweep_two_chairs");
  EXPECT_NO_THROW(requireDisjoint(chairs, kTrainingSeedRange));
  EXPECT_THROW(sweepSceneSet("three_lamps"), InvalidArgumentError);
}

TEST(Progress, ShowsFractionAndEta) {
  std::ostringstream out;
  ProgressBar bar(out, 40, "eval");
  // 10 of 40 done in 30 s: 90 s to go at that rate.
  const std::string line = bar.render(10, 30.0, "random");
  EXPECT_NE(line.find(" 25% 10/40"), std::string::npos) << line;
  EXPECT_NE(line.find("elapsed 30s ETA 1m30s"), std::string::npos) << line;
  EXPECT_NE(line.find("random"), std::string::npos);
  EXPECT_EQ(formatDuration(3725.0), "1h02m");
  EXPECT_EQ(formatDuration(-1.0), "?");
}

}  // namespace
}  // namespace eval
}  // namespace occlusion_env
