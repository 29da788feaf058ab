// Validation of the BEST estimator and the HDI on data with known answers.
#include "occlusion_env/eval/best.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/random.hpp"

namespace occlusion_env {
namespace eval {
namespace {

// Fewer samples than the evaluator's default keep the suite short; still 3 chains.
BestOptions testOptions(std::uint64_t seed) {
  BestOptions options;
  options.chains = 3;
  options.adapt_iterations = 500;
  options.burn_in_iterations = 500;
  options.samples_per_chain = 3000;
  options.seed = seed;
  return options;
}

std::vector<double> normalDraws(std::uint64_t seed, int count, double mean, double sd) {
  RandomSource random(seed);
  std::vector<double> values(count);
  for (auto& value : values) value = random.normal(mean, sd);
  return values;
}

TEST(HighestDensityInterval, NormalSampleGivesMeanPlusMinus196Sd) {
  const auto samples = normalDraws(7, 200000, 3.0, 2.0);
  const Interval hdi = highestDensityInterval(samples, 0.95);
  EXPECT_NEAR(hdi.low, 3.0 - 1.96 * 2.0, 0.05);
  EXPECT_NEAR(hdi.high, 3.0 + 1.96 * 2.0, 0.05);
}

TEST(HighestDensityInterval, SkewedSampleIsShorterThanEqualTailed) {
  // Exponential(1): the 95% HDI is [0, -ln 0.05] = [0, 2.996], narrower than the equal-tailed
  // interval [0.0253, 3.689].
  RandomSource random(11);
  std::vector<double> samples(100000);
  for (auto& value : samples) value = -std::log(1.0 - random.uniform());
  const Interval hdi = highestDensityInterval(samples, 0.95);
  EXPECT_LT(hdi.low, 0.01);
  EXPECT_NEAR(hdi.high, 2.996, 0.05);
}

TEST(HighestDensityInterval, RejectsEmptySampleAndBadMass) {
  EXPECT_THROW(highestDensityInterval({}, 0.95), InvalidArgumentError);
  EXPECT_THROW(highestDensityInterval({1.0, 2.0}, 0.0), InvalidArgumentError);
  EXPECT_THROW(highestDensityInterval({1.0, 2.0}, 1.5), InvalidArgumentError);
}

TEST(PairedBest, HdiCoversKnownMeanDifference) {
  // 50 pairs whose differences have mean 5 and sd 8, for several data and chain seeds.
  for (const std::uint64_t seed : {101u, 202u, 303u, 404u}) {
    const auto first = normalDraws(seed, 50, 30.0, 10.0);
    const auto noise = normalDraws(seed + 1, 50, 0.0, 8.0);
    std::vector<double> second(50);
    for (int i = 0; i < 50; ++i) second[i] = first[i] - 5.0 - noise[i];
    const BestResult result = runPairedBest(first, second, testOptions(seed));
    SCOPED_TRACE("seed " + std::to_string(seed));
    EXPECT_FALSE(result.no_variation);
    EXPECT_EQ(result.pairs, 50);
    EXPECT_LT(result.mu_hdi.low, 5.0);
    EXPECT_GT(result.mu_hdi.high, 5.0);
    // The HDI of 50 values with sd 8 is about +/- 2 * 8 / sqrt(50) = +/- 2.3 wide.
    EXPECT_LT(result.mu_hdi.high - result.mu_hdi.low, 7.0);
    EXPECT_GT(result.probability_mu_positive, 0.95);  // second is faster
    EXPECT_NEAR(result.sigma_mean, 8.0, 3.0);
    EXPECT_GT(result.effect_size_mean, 0.2);
    EXPECT_LT(result.effect_size_hdi.low, result.effect_size_mean);
    EXPECT_GT(result.effect_size_hdi.high, result.effect_size_mean);
    EXPECT_GE(result.nu_mean, 1.0);
    EXPECT_EQ(result.mu_samples.size(), 3u * 3000u);
  }
}

TEST(PairedBest, SameDistributionGivesProbabilityNearHalf) {
  // Two independent draws from one distribution: no credible difference either way.
  for (const std::uint64_t seed : {7u, 8u}) {
    const auto first = normalDraws(seed * 1000, 50, 20.0, 6.0);
    const auto second = normalDraws(seed * 1000 + 1, 50, 20.0, 6.0);
    const BestResult result = runPairedBest(first, second, testOptions(seed));
    SCOPED_TRACE("seed " + std::to_string(seed));
    EXPECT_GT(result.probability_mu_positive, 0.2);
    EXPECT_LT(result.probability_mu_positive, 0.8);
    EXPECT_LT(result.mu_hdi.low, 0.0);
    EXPECT_GT(result.mu_hdi.high, 0.0);
  }
}

TEST(PairedBest, FixedSeedIsBitReproducibleAndOtherSeedDiffers) {
  const auto first = normalDraws(55, 30, 25.0, 9.0);
  const auto second = normalDraws(56, 30, 21.0, 9.0);
  const BestResult a = runPairedBest(first, second, testOptions(42));
  const BestResult b = runPairedBest(first, second, testOptions(42));
  const BestResult c = runPairedBest(first, second, testOptions(43));
  EXPECT_EQ(a.mu_samples, b.mu_samples);
  EXPECT_EQ(a.mu_mean, b.mu_mean);
  EXPECT_EQ(a.mu_hdi.low, b.mu_hdi.low);
  EXPECT_EQ(a.mu_hdi.high, b.mu_hdi.high);
  EXPECT_EQ(a.probability_mu_positive, b.probability_mu_positive);
  EXPECT_EQ(a.effect_size_mean, b.effect_size_mean);
  EXPECT_NE(a.mu_samples, c.mu_samples);
}

TEST(PairedBest, NoVariationIsReportedWithoutMcmc) {
  // Both agents always fail: every difference is 0.
  const std::vector<double> limit(50, 50.0);
  BestOptions options = testOptions(1);
  options.jags_executable = "/nonexistent/jags";  // proves that JAGS is not run
  const BestResult zero = runPairedBest(limit, limit, options);
  EXPECT_TRUE(zero.no_variation);
  EXPECT_EQ(zero.sample_mean, 0.0);
  EXPECT_NE(zero.note.find("no variation"), std::string::npos);
  EXPECT_TRUE(std::isnan(zero.probability_mu_positive));
  EXPECT_TRUE(zero.mu_samples.empty());

  std::vector<double> shifted(50, 47.0);
  const BestResult constant = runPairedBest(limit, shifted, options);
  EXPECT_TRUE(constant.no_variation);
  EXPECT_EQ(constant.sample_mean, 3.0);
}

TEST(PairedBest, RejectsBadInput) {
  EXPECT_THROW(runPairedBest({1.0, 2.0}, {1.0}, testOptions(1)), InvalidArgumentError);
  EXPECT_THROW(runBest({1.0}, testOptions(1)), InvalidArgumentError);
  EXPECT_THROW(runBest({1.0, NAN}, testOptions(1)), InvalidArgumentError);
}

TEST(PairedBest, MissingJagsNamesThePackage) {
  BestOptions options = testOptions(1);
  options.jags_executable = "/nonexistent/jags";
  try {
    runBest({1.0, 2.0, 4.0}, options);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("'jags'"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace eval
}  // namespace occlusion_env
