// The Markdown summary of episode records (agents/episode.hpp): Table 4 of the paper (success
// rate, mean and standard deviation of steps per agent) and Table 5 (paired BEST for every pair
// of agents), with the paper's figures beside ours.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "occlusion_env/agents/agent_registry.hpp"
#include "occlusion_env/agents/episode.hpp"
#include "occlusion_env/eval/best.hpp"

namespace occlusion_env {
namespace eval {

struct AgentSummary {
  std::string agent;
  std::string paper_label;  // the paper's name for the method, "" if it has none
  int episodes = 0;
  int successes = 0;
  int max_steps = 0;        // the largest step limit among its episodes
  double mean_steps = 0.0;  // failed episodes counted as the step limit
  double sd_steps = 0.0;    // sample standard deviation (n - 1)
  double mean_wall_time_s = 0.0;
  bool competes = true;  // false for a reference (the oracle): no BEST, no "above" figure
  /// Mean of (counted steps - the reference's counted steps) over the scenes both ran: how far
  /// above the floor; NaN when no reference agent is among the records.
  double mean_steps_above_reference = 0.0;
};

/// One summary per agent, in the order agents first appear in `records`; paper labels and
/// whether an agent competes from `registry` (agents it does not know compete and have no label).
/// The reference is the first non-competing agent in `records` (the oracle). Throws
/// InvalidArgumentError when an episode was cut short (it is no outcome of the agent: run it
/// again).
std::vector<AgentSummary> summarizeAgents(const std::vector<EpisodeRecord>& records,
                                          const AgentRegistry& registry);

struct PairComparison {
  std::string first;   // the baseline ("Baseline" in Table 5)
  std::string second;  // the compared method ("Method")
  BestResult best;     // on counted steps, first - second: mu > 0 means second is faster
};

/// Paired BEST for every pair (i < j) of competing agents (registry) in order of appearance,
/// paired on (scene seed, start azimuth); scenes one agent lacks are left out. Throws
/// InvalidArgumentError when a pair shares fewer than 2 scenes.
std::vector<PairComparison> compareAgents(const std::vector<EpisodeRecord>& records,
                                          const AgentRegistry& registry,
                                          const BestOptions& options = {});

/// The paper's Table 4 figures for a method, by the paper's label ("Env. Grad").
struct PaperAgentFigures {
  double mean_steps;
  double sd_steps;
};
std::optional<PaperAgentFigures> paperAgentFigures(const std::string& paper_label);

/// The paper's Table 5 entry for (baseline, method), by the paper's labels, where it has one.
struct PaperPairFigures {
  double hdi_low;
  double hdi_high;
  double difference_of_means;
  double confidence_percent;
};
std::optional<PaperPairFigures> paperPairFigures(const std::string& first,
                                                 const std::string& second);

/// The Markdown document: a title, `preamble` (free text, e.g. how it was produced), Table 4 and
/// Table 5 layouts with the paper's figures beside ours (matched through the summaries' labels).
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
