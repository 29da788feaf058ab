// Episode records (one CSV row per agent and scene) and the Markdown summary built from them:
// Table 4 of the paper (success rate, mean and standard deviation of steps per agent) and
// Table 5 (paired BEST for every pair of agents).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "occlusion_env/eval/best.hpp"

namespace occlusion_env {
namespace eval {

struct EpisodeRecord {
  std::string agent;
  std::string scene_set;  // the scene set's name, or "sweep_<preset>"
  std::uint64_t scene_seed = 0;
  double start_azimuth_rad = 0.0;
  int max_steps = 0;     // the step limit of the run
  int steps = 0;         // steps taken (max_steps when the episode failed)
  bool success = false;  // occlusion reached the threshold within max_steps
  double final_occlusion_px = 0.0;
  double wall_time_s = 0.0;

  /// Steps for the statistics: a failed episode counts as the step limit.
  int countedSteps() const { return success ? steps : max_steps; }
};

/// The CSV header line (no newline) and one row; agent and scene set names must not hold commas,
/// quotes or newlines (InvalidArgumentError).
std::string episodeCsvHeader();
void writeEpisodeCsvRow(std::ostream& out, const EpisodeRecord& record);
/// Reads a file written with the two functions above. Throws InvalidArgumentError naming the line.
std::vector<EpisodeRecord> readEpisodeCsv(const std::string& path);

struct AgentSummary {
  std::string agent;
  int episodes = 0;
  int successes = 0;
  int max_steps = 0;        // the largest step limit among its episodes
  double mean_steps = 0.0;  // failed episodes counted as the step limit
  double sd_steps = 0.0;    // sample standard deviation (n - 1)
  double mean_wall_time_s = 0.0;
};

/// One summary per agent, in the order agents first appear in `records`.
std::vector<AgentSummary> summarizeAgents(const std::vector<EpisodeRecord>& records);

struct PairComparison {
  std::string first;   // the baseline ("Baseline" in Table 5)
  std::string second;  // the compared method ("Method")
  BestResult best;     // on counted steps, first - second: mu > 0 means second is faster
};

/// Paired BEST for every pair (i < j) of agents in order of appearance, paired on
/// (scene seed, start azimuth); scenes one agent lacks are left out. Throws InvalidArgumentError
/// when a pair shares fewer than 2 scenes.
std::vector<PairComparison> compareAgents(const std::vector<EpisodeRecord>& records,
                                          const BestOptions& options = {});

/// The paper's figures for an agent (Table 4) by our agent name, where the paper has one.
struct PaperAgentFigures {
  std::string label;  // the paper's column label, e.g. "Env. Grad"
  double mean_steps;
  double sd_steps;
};
std::optional<PaperAgentFigures> paperAgentFigures(const std::string& agent);

/// The paper's Table 5 entry for (baseline, method), where it has one.
struct PaperPairFigures {
  double hdi_low;
  double hdi_high;
  double difference_of_means;
  double confidence_percent;
};
std::optional<PaperPairFigures> paperPairFigures(const std::string& first,
                                                 const std::string& second);

/// The Markdown document: a title, `preamble` (free text, e.g. how it was produced), Table 4 and
/// Table 5 layouts with the paper's figures beside ours.
std::string renderSummaryMarkdown(const std::string& title, const std::string& preamble,
                                  const std::vector<AgentSummary>& agents,
                                  const std::vector<PairComparison>& comparisons);

/// Posterior samples of mu for every pair: "first,second,mu" rows (for the Figure A1 plot).
void writePosteriorSamplesCsv(const std::vector<PairComparison>& comparisons,
                              const std::string& path);
/// One row per pair with the BEST figures (for the plot's HDI bars and for other tools).
void writeComparisonCsv(const std::vector<PairComparison>& comparisons, const std::string& path);

}  // namespace eval
}  // namespace occlusion_env
