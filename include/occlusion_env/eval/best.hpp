// Kruschke's BEST (Bayesian estimation supersedes the t test, 2013) for paired samples, run with
// JAGS: a one-sample BEST on the differences d_i = first_i - second_i.
//
// Model: d_i ~ t(mu, sigma, nu); mu ~ N(mean(d), (1000 sd(d))^2); sigma ~ U(sd(d) / 1000,
// 1000 sd(d)); nu - 1 ~ Exp(1/29). With step counts, mu > 0 means the second agent needs fewer
// steps than the first (Table 5's "confidence" of the paper is P(mu > 0) in percent).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace occlusion_env {
namespace eval {

/// The JAGS model text (BUGS language) the estimator writes to model.bug.
extern const char* const kPairedBestModel;

struct BestOptions {
  int chains = 3;
  int adapt_iterations = 500;     // per chain, JAGS adaptation before burn-in
  int burn_in_iterations = 1000;  // per chain, discarded
  int samples_per_chain = 10000;  // kept per chain
  std::uint64_t seed = 20130601;  // derives each chain's Mersenne-Twister seed
  double credible_mass = 0.95;    // of the highest-density intervals
  std::string jags_executable = "/usr/bin/jags";
  bool keep_work_dir = false;  // keep the temporary JAGS files (for debugging)
};

/// A closed interval [low, high].
struct Interval {
  double low = 0.0;
  double high = 0.0;
};

struct BestResult {
  int pairs = 0;
  double sample_mean = 0.0;  // mean of the differences
  double sample_sd = 0.0;    // their standard deviation (n - 1)
  /// True when every difference is the same (sd = 0): the model is undefined, no MCMC ran, and
  /// only `sample_mean` and `note` are meaningful (the posterior fields are NaN).
  bool no_variation = false;
  std::string note;  // human-readable remark, e.g. "no variation: every difference is 0"

  double mu_mean = 0.0;                  // posterior mean of the mean difference
  Interval mu_hdi;                       // its highest-density interval
  double probability_mu_positive = 0.0;  // P(mu > 0): the second needs fewer steps
  double sigma_mean = 0.0;
  double nu_mean = 0.0;
  double nu_median = 0.0;
  double log10_nu_mean = 0.0;     // Kruschke's plots show log10(nu)
  double effect_size_mean = 0.0;  // posterior mean of mu / sigma
  Interval effect_size_hdi;
  std::vector<double> mu_samples;  // every chain's kept samples, chain after chain
};

/// Shortest interval holding `mass` of `samples` (Kruschke's HDIofMCMC). Throws
/// InvalidArgumentError for an empty sample or a mass outside (0, 1].
Interval highestDensityInterval(std::vector<double> samples, double mass);

/// One-sample BEST on `differences`. Throws InvalidArgumentError for fewer than 2 values or
/// non-finite ones, std::runtime_error when JAGS is missing (naming the Debian package) or fails
/// (with the end of its log).
BestResult runBest(const std::vector<double>& differences, const BestOptions& options = {});

/// Paired BEST on first[i] - second[i]. Throws InvalidArgumentError for different lengths.
BestResult runPairedBest(const std::vector<double>& first, const std::vector<double>& second,
                         const BestOptions& options = {});

}  // namespace eval
}  // namespace occlusion_env
