#include "occlusion_env/eval/best.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/random.hpp"
#include "occlusion_env/common/statistics.hpp"
#include "occlusion_env/eval/subprocess.hpp"

namespace occlusion_env {
namespace eval {

namespace fs = std::filesystem;

const char* const kPairedBestModel = R"(# One-sample BEST (Kruschke 2013) on paired differences y.
model {
  for (i in 1:n) {
    y[i] ~ dt(mu, tau, nu)
  }
  mu ~ dnorm(mu_prior_mean, mu_prior_precision)
  tau <- 1 / pow(sigma, 2)
  sigma ~ dunif(sigma_low, sigma_high)
  nu_minus_one ~ dexp(1 / 29)
  nu <- nu_minus_one + 1
}
)";

namespace {

// R dump format needs round-trippable doubles.
std::string formatDouble(double value) {
  std::ostringstream out;
  out << std::setprecision(17) << value;
  return out.str();
}

void writeFile(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error("BEST: cannot write " + path.string());
}

std::string readTail(const fs::path& path, std::size_t max_chars) {
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.size() > max_chars) text = "..." + text.substr(text.size() - max_chars);
  return text;
}

// A fresh private directory under the system's temporary directory, removed on destruction.
class TemporaryDirectory {
 public:
  explicit TemporaryDirectory(bool keep) : keep_(keep) {
    std::string pattern = (fs::temp_directory_path() / "occlusion_best_XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) {
      throw std::runtime_error("BEST: cannot create a temporary directory: " +
                               std::string(std::strerror(errno)));
    }
    path_ = pattern;
  }
  ~TemporaryDirectory() {
    std::error_code ignored;
    if (!keep_) fs::remove_all(path_, ignored);
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
  bool keep_;
};

// CODAindex.txt: "name first last" (1-based line numbers within every chain file).
std::map<std::string, std::pair<std::size_t, std::size_t>> readCodaIndex(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("BEST: JAGS wrote no " + path.string());
  std::map<std::string, std::pair<std::size_t, std::size_t>> index;
  std::string name;
  std::size_t first = 0;
  std::size_t last = 0;
  while (in >> name >> first >> last) index[name] = {first, last};
  return index;
}

// CODAchainK.txt: "iteration value" per line.
std::vector<double> readCodaValues(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("BEST: JAGS wrote no " + path.string());
  std::vector<double> values;
  double iteration = 0.0;
  double value = 0.0;
  while (in >> iteration >> value) values.push_back(value);
  return values;
}

double sampleStandardDeviation(const std::vector<double>& values, double values_mean) {
  double sum_squares = 0.0;
  for (const double value : values) sum_squares += (value - values_mean) * (value - values_mean);
  return std::sqrt(sum_squares / static_cast<double>(values.size() - 1));
}

void validateOptions(const BestOptions& options) {
  if (options.chains < 1 || options.samples_per_chain < 10 || options.burn_in_iterations < 0 ||
      options.adapt_iterations < 0) {
    throw InvalidArgumentError(
        "BEST: need chains >= 1, samples_per_chain >= 10, burn-in and adaptation >= 0");
  }
  if (!(options.credible_mass > 0.0 && options.credible_mass <= 1.0)) {
    throw InvalidArgumentError("BEST: credible_mass must be in (0, 1]");
  }
}

}  // namespace

Interval highestDensityInterval(std::vector<double> samples, double mass) {
  if (samples.empty()) throw InvalidArgumentError("HDI of an empty sample");
  if (!(mass > 0.0 && mass <= 1.0)) throw InvalidArgumentError("HDI mass must be in (0, 1]");
  std::sort(samples.begin(), samples.end());
  // The window spans `included` consecutive order statistics; pick the narrowest.
  const std::size_t count = samples.size();
  const std::size_t included =
      std::min(count, static_cast<std::size_t>(std::ceil(mass * static_cast<double>(count))));
  const std::size_t span = included > 0 ? included - 1 : 0;
  std::size_t best_start = 0;
  double best_width = samples[span] - samples[0];
  for (std::size_t start = 1; start + span < count; ++start) {
    const double width = samples[start + span] - samples[start];
    if (width < best_width) {
      best_width = width;
      best_start = start;
    }
  }
  return {samples[best_start], samples[best_start + span]};
}

namespace {

// The model, data, per-chain start values and the JAGS script in `dir`.
void writeJagsInputs(const fs::path& dir, const std::vector<double>& differences,
                     double sample_mean, double sample_sd, const BestOptions& options) {
  writeFile(dir / "model.bug", kPairedBestModel);

  std::ostringstream data;
  data << "\"n\" <- " << differences.size() << "\n\"y\" <- c(";
  for (std::size_t i = 0; i < differences.size(); ++i) {
    data << (i > 0 ? ", " : "") << formatDouble(differences[i]);
  }
  data << ")\n";
  data << "\"mu_prior_mean\" <- " << formatDouble(sample_mean) << "\n";
  data << "\"mu_prior_precision\" <- " << formatDouble(1.0 / std::pow(1000.0 * sample_sd, 2))
       << "\n";
  data << "\"sigma_low\" <- " << formatDouble(sample_sd / 1000.0) << "\n";
  data << "\"sigma_high\" <- " << formatDouble(sample_sd * 1000.0) << "\n";
  writeFile(dir / "data.R", data.str());

  // Each chain: its own Mersenne-Twister seed from `options.seed`, and Kruschke's start values.
  std::ostringstream script;
  script << "model in \"model.bug\"\ndata in \"data.R\"\ncompile, nchains(" << options.chains
         << ")\n";
  RandomSource seeds(options.seed);
  for (int chain = 1; chain <= options.chains; ++chain) {
    const std::uint64_t chain_seed = 1 + seeds.below(2147483646ULL);  // JAGS takes an int
    std::ostringstream inits;
    inits << "\".RNG.name\" <- \"base::Mersenne-Twister\"\n"
          << "\".RNG.seed\" <- " << chain_seed << "\n"
          << "\"mu\" <- " << formatDouble(sample_mean) << "\n"
          << "\"sigma\" <- " << formatDouble(sample_sd) << "\n"
          << "\"nu_minus_one\" <- 4\n";
    const std::string file = "inits" + std::to_string(chain) + ".R";
    writeFile(dir / file, inits.str());
    script << "parameters in \"" << file << "\", chain(" << chain << ")\n";
  }
  script << "initialize\n";
  if (options.adapt_iterations > 0) script << "adapt " << options.adapt_iterations << "\n";
  if (options.burn_in_iterations > 0) script << "update " << options.burn_in_iterations << "\n";
  script << "monitor mu\nmonitor sigma\nmonitor nu\n"
         << "update " << options.samples_per_chain << "\n"
         << "coda *, stem(CODA)\nexit\n";
  writeFile(dir / "script.cmd", script.str());
}

struct PosteriorSamples {
  std::vector<double> mu, sigma, nu;  // all chains, one after the other
};

// The monitored samples of every chain from JAGS's CODA output in `dir`.
PosteriorSamples readPosteriorSamples(const fs::path& dir, int chains) {
  const auto index = readCodaIndex(dir / "CODAindex.txt");
  for (const char* name : {"mu", "sigma", "nu"}) {
    if (index.count(name) == 0) {
      throw std::runtime_error(std::string("BEST: CODAindex.txt lacks ") + name + ": " +
                               readTail(dir / "jags.log", 1500));
    }
  }
  PosteriorSamples samples;
  for (int chain = 1; chain <= chains; ++chain) {
    const std::vector<double> values =
        readCodaValues(dir / ("CODAchain" + std::to_string(chain) + ".txt"));
    auto append = [&](const char* name, std::vector<double>& target) {
      const auto [first, last] = index.at(name);
      if (first < 1 || last > values.size() || first > last) {
        throw std::runtime_error("BEST: truncated CODA output for chain " + std::to_string(chain));
      }
      target.insert(target.end(), values.begin() + static_cast<std::ptrdiff_t>(first - 1),
                    values.begin() + static_cast<std::ptrdiff_t>(last));
    };
    append("mu", samples.mu);
    append("sigma", samples.sigma);
    append("nu", samples.nu);
  }
  if (samples.mu.size() != samples.sigma.size() || samples.mu.size() != samples.nu.size() ||
      samples.mu.empty()) {
    throw std::runtime_error("BEST: inconsistent CODA output");
  }
  return samples;
}

// Posterior means, HDIs and P(mu > 0) into `result`.
void summarizePosterior(PosteriorSamples samples, double credible_mass, BestResult& result) {
  const std::size_t n = samples.mu.size();
  std::vector<double> effect_size(n);
  std::vector<double> log10_nu(n);
  std::size_t positive = 0;
  for (std::size_t i = 0; i < n; ++i) {
    effect_size[i] = samples.mu[i] / samples.sigma[i];
    log10_nu[i] = std::log10(samples.nu[i]);
    if (samples.mu[i] > 0.0) ++positive;
  }
  result.mu_mean = mean(samples.mu);
  result.mu_hdi = highestDensityInterval(samples.mu, credible_mass);
  result.probability_mu_positive = static_cast<double>(positive) / static_cast<double>(n);
  result.sigma_mean = mean(samples.sigma);
  result.nu_mean = mean(samples.nu);
  result.nu_median = median(samples.nu);
  result.log10_nu_mean = mean(log10_nu);
  result.effect_size_mean = mean(effect_size);
  result.effect_size_hdi = highestDensityInterval(effect_size, credible_mass);
  result.mu_samples = std::move(samples.mu);
}

}  // namespace

BestResult runBest(const std::vector<double>& differences, const BestOptions& options) {
  validateOptions(options);
  if (differences.size() < 2) throw InvalidArgumentError("BEST needs at least 2 differences");
  for (const double value : differences) {
    if (!std::isfinite(value)) throw InvalidArgumentError("BEST: non-finite difference");
  }

  BestResult result;
  result.pairs = static_cast<int>(differences.size());
  result.sample_mean = mean(differences);
  result.sample_sd = sampleStandardDeviation(differences, result.sample_mean);

  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto [min_it, max_it] = std::minmax_element(differences.begin(), differences.end());
  if (*min_it == *max_it) {
    // The priors scale with sd(y) = 0: the model is undefined, so no MCMC.
    result.no_variation = true;
    result.note = "no variation: every difference is " + formatDouble(*min_it);
    result.mu_mean = result.sample_mean;
    result.mu_hdi = {nan, nan};
    result.probability_mu_positive = nan;
    result.sigma_mean = result.nu_mean = result.nu_median = result.log10_nu_mean = nan;
    result.effect_size_mean = nan;
    result.effect_size_hdi = {nan, nan};
    return result;
  }

  if (access(options.jags_executable.c_str(), X_OK) != 0) {
    throw std::runtime_error("BEST: JAGS not found at " + options.jags_executable +
                             " (install the Debian package 'jags': apt-get install jags)");
  }
  TemporaryDirectory work_dir(options.keep_work_dir);
  writeJagsInputs(work_dir.path(), differences, result.sample_mean, result.sample_sd, options);
  const int status = runProgram({options.jags_executable, "script.cmd"}, work_dir.path().string(),
                                (work_dir.path() / "jags.log").string());
  if (status != 0) {
    throw std::runtime_error("BEST: jags exited with status " + std::to_string(status) + ": " +
                             readTail(work_dir.path() / "jags.log", 1500));
  }
  summarizePosterior(readPosteriorSamples(work_dir.path(), options.chains), options.credible_mass,
                     result);
  return result;
}

BestResult runPairedBest(const std::vector<double>& first, const std::vector<double>& second,
                         const BestOptions& options) {
  if (first.size() != second.size()) {
    throw InvalidArgumentError("paired BEST: " + std::to_string(first.size()) + " vs " +
                               std::to_string(second.size()) + " values");
  }
  std::vector<double> differences(first.size());
  for (std::size_t i = 0; i < first.size(); ++i) differences[i] = first[i] - second[i];
  return runBest(differences, options);
}

}  // namespace eval
}  // namespace occlusion_env
