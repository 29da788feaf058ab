#include "occlusion_env/eval/summary.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace eval {

namespace {

std::string fixed(double value, int digits) {
  if (!std::isfinite(value)) return "n/a";
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

// The key pairing two agents' episodes: the same scene seen from the same start azimuth.
std::pair<std::uint64_t, long long> sceneKey(const EpisodeRecord& record) {
  return {record.scene_seed, std::llround(record.start_azimuth_rad * 1e9)};  // nrad resolution
}

std::vector<std::string> agentsInOrder(const std::vector<EpisodeRecord>& records) {
  std::vector<std::string> agents;
  for (const auto& record : records) {
    if (std::find(agents.begin(), agents.end(), record.agent) == agents.end()) {
      agents.push_back(record.agent);
    }
  }
  return agents;
}

// "name (Paper label)" when the paper has the method.
std::string agentLabel(const std::string& agent, const std::string& paper_label) {
  return paper_label.empty() ? agent : agent + " (" + paper_label + ")";
}

}  // namespace

std::vector<AgentSummary> summarizeAgents(const std::vector<EpisodeRecord>& records,
                                          const AgentRegistry& registry) {
  for (const auto& record : records) {
    if (!record.completed()) {
      throw InvalidArgumentError("the " + record.agent + " episode on scene " +
                                 std::to_string(record.scene_seed) + " was cut short (" +
                                 toString(record.end) + ": " + record.message +
                                 "); run it again before summarising");
    }
  }
  const auto competes = [&registry](const std::string& agent) {
    const AgentEntry* entry = registry.find(agent);
    return entry == nullptr || entry->competes;
  };
  // The reference's counted steps per scene.
  std::map<std::pair<std::uint64_t, long long>, double> reference;
  for (const auto& agent : agentsInOrder(records)) {
    if (competes(agent)) continue;
    for (const auto& record : records) {
      if (record.agent == agent) reference[sceneKey(record)] = record.countedSteps();
    }
    break;
  }
  std::vector<AgentSummary> summaries;
  for (const auto& agent : agentsInOrder(records)) {
    std::vector<EpisodeRecord> own;
    for (const auto& record : records) {
      if (record.agent == agent) own.push_back(record);
    }
    const EpisodeStatistics stats = summarizeEpisodes(own);
    AgentSummary summary;
    summary.agent = agent;
    if (const AgentEntry* entry = registry.find(agent)) summary.paper_label = entry->paper_label;
    summary.episodes = stats.completed;
    summary.successes = stats.successes;
    summary.max_steps = stats.max_steps;
    summary.mean_steps = stats.mean_steps;
    summary.sd_steps = stats.sd_steps;
    summary.mean_wall_time_s = stats.mean_wall_time_s;
    summary.competes = competes(agent);
    double above = 0.0;
    int shared = 0;
    for (const auto& record : own) {
      const auto found = reference.find(sceneKey(record));
      if (found == reference.end()) continue;
      above += record.countedSteps() - found->second;
      ++shared;
    }
    summary.mean_steps_above_reference =
        shared > 0 ? above / shared : std::numeric_limits<double>::quiet_NaN();
    summaries.push_back(summary);
  }
  return summaries;
}

std::vector<PairComparison> compareAgents(const std::vector<EpisodeRecord>& records,
                                          const AgentRegistry& registry,
                                          const BestOptions& options) {
  std::vector<std::string> agents;
  for (const auto& agent : agentsInOrder(records)) {
    const AgentEntry* entry = registry.find(agent);
    if (entry == nullptr || entry->competes) agents.push_back(agent);
  }
  // agent -> scene -> counted steps
  std::map<std::string, std::map<std::pair<std::uint64_t, long long>, double>> steps;
  for (const auto& record : records) steps[record.agent][sceneKey(record)] = record.countedSteps();

  std::vector<PairComparison> comparisons;
  for (std::size_t i = 0; i < agents.size(); ++i) {
    for (std::size_t j = i + 1; j < agents.size(); ++j) {
      std::vector<double> first;
      std::vector<double> second;
      for (const auto& [scene, first_steps] : steps[agents[i]]) {
        const auto other = steps[agents[j]].find(scene);
        if (other == steps[agents[j]].end()) continue;
        first.push_back(first_steps);
        second.push_back(other->second);
      }
      if (first.size() < 2) {
        throw InvalidArgumentError("agents " + occlusion_env::quoted(agents[i]) + " and " +
                                   occlusion_env::quoted(agents[j]) + " share " +
                                   std::to_string(first.size()) +
                                   " scenes; paired BEST needs at least 2");
      }
      comparisons.push_back({agents[i], agents[j], runPairedBest(first, second, options)});
    }
  }
  return comparisons;
}

std::optional<PaperAgentFigures> paperAgentFigures(const std::string& paper_label) {
  // Table 4 of Szemenyei & Szanto 2023 (50 scenes, 3 random ShapeNet objects, azimuth 0).
  static const std::map<std::string, PaperAgentFigures> kTable4 = {
      {"Random", {31.5, 13.9}},  {"Env. Grad", {20.8, 10.2}}, {"Pred. Grad", {18.5, 8.2}},
      {"Agent-UN", {15.9, 4.1}}, {"Agent-IN", {15.8, 3.8}},
  };
  const auto found = kTable4.find(paper_label);
  if (found == kTable4.end()) return std::nullopt;
  return found->second;
}

std::optional<PaperPairFigures> paperPairFigures(const std::string& first,
                                                 const std::string& second) {
  // Table 5 of the paper: baseline -> method, difference = baseline - method.
  static const std::map<std::pair<std::string, std::string>, PaperPairFigures> kTable5 = {
      {{"Random", "Env. Grad"}, {6.42, 14.97, 10.73, 100.0}},
      {{"Random", "Pred. Grad"}, {9.15, 17.0, 12.98, 100.0}},
      {{"Random", "Agent-IN"}, {11.69, 19.36, 15.58, 100.0}},
      {{"Env. Grad", "Pred. Grad"}, {-0.21, 2.43, 1.03, 94.6}},
      {{"Env. Grad", "Agent-IN"}, {2.11, 6.74, 4.34, 100.0}},
      {{"Pred. Grad", "Agent-IN"}, {0.05, 1.63, 0.84, 98.47}},
  };
  const auto found = kTable5.find({first, second});
  if (found == kTable5.end()) return std::nullopt;
  return found->second;
}

namespace {

// An agent's row label: its name, with the paper's label where it has one (`paper_labels` maps
// the names to the labels).
std::string rowLabel(std::map<std::string, std::string>& paper_labels, const std::string& agent) {
  return agentLabel(agent, paper_labels[agent]);
}

// The Table 4 section: one row per agent.
void writeAgentTable(std::ostream& md, const std::vector<AgentSummary>& agents,
                     std::map<std::string, std::string>& paper_labels) {
  md << "## Steps to an unoccluded view (Table 4 layout)\n\n"
     << "Failed episodes (no unoccluded view within the step limit) are counted with the step "
        "limit. Paper: Table 4 of Szemenyei & Szanto 2023 (50 scenes of 3 random ShapeNet objects, "
        "PyTorch3D renderer); ours are on our own scenes and renderer, so only the ordering and "
        "rough size are comparable.\n\n";
  const bool with_reference =
      std::any_of(agents.begin(), agents.end(), [](const AgentSummary& a) { return !a.competes; });
  if (with_reference) {
    md << "The oracle (a reference, not a competitor: it renders other poses to find the fewest "
          "steps to an unoccluded view) gives the floor; \"Above oracle\" is each agent's mean "
          "of its counted steps minus the oracle's on the same scene.\n\n";
  }
  md << "| Agent | Episodes | Successes | Success rate | Failed (counted as limit) | Mean steps "
        "| Std |"
     << (with_reference ? " Above oracle |" : "")
     << " Paper mean | Paper std | Wall time / episode [s] |\n"
     << "|---|---:|---:|---:|---:|---:|---:|" << (with_reference ? "---:|" : "")
     << "---:|---:|---:|\n";
  for (const auto& agent : agents) {
    const auto paper = paperAgentFigures(agent.paper_label);
    const int failed = agent.episodes - agent.successes;
    md << "| " << rowLabel(paper_labels, agent.agent) << " | " << agent.episodes << " | "
       << agent.successes << " | " << fixed(100.0 * agent.successes / agent.episodes, 1) << " % | "
       << failed << " (" << agent.max_steps << ") | " << fixed(agent.mean_steps, 1) << " | "
       << fixed(agent.sd_steps, 1) << " | "
       << (with_reference
               ? (agent.competes ? fixed(agent.mean_steps_above_reference, 1) : "(floor)") + " | "
               : "")
       << (paper ? fixed(paper->mean_steps, 1) : "-") << " | "
       << (paper ? fixed(paper->sd_steps, 1) : "-") << " | " << fixed(agent.mean_wall_time_s, 3)
       << " |\n";
  }
}

// The Table 5 section: one row per pair, then a note for each pair BEST skipped.
void writeComparisonTable(std::ostream& md, const std::vector<PairComparison>& comparisons,
                          std::map<std::string, std::string>& paper_labels) {
  md << "\n## Paired Bayesian estimation (BEST; Table 5 layout)\n\n"
     << "Kruschke's BEST on the paired differences of counted steps, Baseline - Method, per "
        "scene: mu is the mean difference, mu > 0 means the Method needs fewer steps. "
        "Confidence = P(mu > 0) in percent; HDI = 95% highest-density interval; effect size = "
        "mu / sigma. The t likelihood is robust: with heavy tails (small nu) mu follows the bulk "
        "of "
        "the differences and can differ from the sample mean difference, shown beside it. "
        "Paper figures where the paper has the pair.\n\n";
  md << "| Baseline | Method | Pairs | HDI low | HDI high | Diff of means | Confidence [%] | "
        "Effect size | Effect size HDI | nu (median) | Sample mean diff | Paper: HDI, diff, "
        "confidence |\n"
     << "|---|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---|\n";
  for (const auto& pair : comparisons) {
    const auto& best = pair.best;
    const auto paper = paperPairFigures(paper_labels[pair.first], paper_labels[pair.second]);
    const std::string paper_text = paper ? "[" + fixed(paper->hdi_low, 2) + ", " +
                                               fixed(paper->hdi_high, 2) + "], " +
                                               fixed(paper->difference_of_means, 2) + ", " +
                                               fixed(paper->confidence_percent, 2) + " %"
                                         : "-";
    md << "| " << rowLabel(paper_labels, pair.first) << " | " << rowLabel(paper_labels, pair.second)
       << " | " << best.pairs << " | ";
    if (best.no_variation) {
      md << "- | - | " << fixed(best.sample_mean, 2) << " | - | - | - | - | "
         << fixed(best.sample_mean, 2) << " | " << paper_text << " |\n";
      continue;
    }
    md << fixed(best.mu_hdi.low, 2) << " | " << fixed(best.mu_hdi.high, 2) << " | "
       << fixed(best.mu_mean, 2) << " | " << fixed(100.0 * best.probability_mu_positive, 2) << " | "
       << fixed(best.effect_size_mean, 2) << " | [" << fixed(best.effect_size_hdi.low, 2) << ", "
       << fixed(best.effect_size_hdi.high, 2) << "] | " << fixed(best.nu_median, 1) << " | "
       << fixed(best.sample_mean, 2) << " | " << paper_text << " |\n";
  }
  for (const auto& pair : comparisons) {
    if (pair.best.no_variation) {
      md << "\n"
         << pair.first << " vs " << pair.second << ": " << pair.best.note
         << " (BEST skipped: the model needs sd > 0).\n";
    }
  }
}

}  // namespace

std::string renderSummaryMarkdown(const std::string& title, const std::string& preamble,
                                  const std::vector<AgentSummary>& agents,
                                  const std::vector<PairComparison>& comparisons) {
  std::map<std::string, std::string> paper_labels;
  for (const auto& agent : agents) paper_labels[agent.agent] = agent.paper_label;
  std::ostringstream md;
  md << "# " << title << "\n\n";
  if (!preamble.empty()) md << preamble << "\n\n";
  writeAgentTable(md, agents, paper_labels);
  if (!comparisons.empty()) writeComparisonTable(md, comparisons, paper_labels);
  return md.str();
}

void writePosteriorSamplesCsv(const std::vector<PairComparison>& comparisons,
                              const std::string& path) {
  std::ofstream out(path);
  out << "first,second,mu\n" << std::setprecision(9);
  for (const auto& pair : comparisons) {
    for (const double mu : pair.best.mu_samples) {
      out << pair.first << ',' << pair.second << ',' << mu << '\n';
    }
  }
  if (!out) throw InvalidArgumentError("cannot write " + path);
}

void writeComparisonCsv(const std::vector<PairComparison>& comparisons, const std::string& path) {
  std::ofstream out(path);
  out << "first,second,pairs,no_variation,sample_mean,mu_mean,mu_hdi_low,mu_hdi_high,"
         "probability_second_fewer_steps,effect_size_mean,effect_size_hdi_low,"
         "effect_size_hdi_high,sigma_mean,nu_median\n"
      << std::setprecision(9);
  for (const auto& pair : comparisons) {
    const auto& best = pair.best;
    out << pair.first << ',' << pair.second << ',' << best.pairs << ','
        << (best.no_variation ? 1 : 0) << ',' << best.sample_mean << ',' << best.mu_mean << ','
        << best.mu_hdi.low << ',' << best.mu_hdi.high << ',' << best.probability_mu_positive << ','
        << best.effect_size_mean << ',' << best.effect_size_hdi.low << ','
        << best.effect_size_hdi.high << ',' << best.sigma_mean << ',' << best.nu_median << '\n';
  }
  if (!out) throw InvalidArgumentError("cannot write " + path);
}

}  // namespace eval
}  // namespace occlusion_env
