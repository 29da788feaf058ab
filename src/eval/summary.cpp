#include "occlusion_env/eval/summary.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

#include "occlusion_env/core/errors.hpp"

namespace occlusion_env {
namespace eval {

namespace {

void requirePlainName(const std::string& name, const char* what) {
  if (name.empty() || name.find_first_of(",\"\n\r") != std::string::npos) {
    throw InvalidArgumentError(std::string("CSV ") + what +
                               " must be non-empty without commas, "
                               "quotes or newlines: " +
                               quoted(name));
  }
}

std::vector<std::string> splitCsvLine(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

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

std::string agentLabel(const std::string& agent) {
  const auto paper = paperAgentFigures(agent);
  return paper ? agent + " (" + paper->label + ")" : agent;
}

}  // namespace

std::string episodeCsvHeader() {
  return "agent,scene_set,scene_seed,start_azimuth_rad,max_steps,steps,success,"
         "final_occlusion_px,wall_time_s";
}

void writeEpisodeCsvRow(std::ostream& out, const EpisodeRecord& record) {
  requirePlainName(record.agent, "agent name");
  requirePlainName(record.scene_set, "scene set name");
  std::ostringstream row;
  row << std::setprecision(17) << record.agent << ',' << record.scene_set << ','
      << record.scene_seed << ',' << record.start_azimuth_rad << ',' << record.max_steps << ','
      << record.steps << ',' << (record.success ? 1 : 0) << ',' << record.final_occlusion_px << ','
      << std::setprecision(6) << record.wall_time_s << '\n';
  out << row.str();
}

std::vector<EpisodeRecord> readEpisodeCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidArgumentError("cannot read episode CSV " + path);
  std::string line;
  // Files with more columns after ours (the agent nodes' CSVs) are read too; an agent node's
  // `completed` column must then be 1 everywhere: a cut-short episode is no agent outcome.
  const std::string header = episodeCsvHeader();
  if (!std::getline(in, line) ||
      (line != header && line.compare(0, header.size() + 1, header + ",") != 0)) {
    throw InvalidArgumentError(path + ": line 1 does not start with the header '" + header + "'");
  }
  const std::vector<std::string> columns = splitCsvLine(line);
  const auto completed_column = std::find(columns.begin(), columns.end(), "completed");
  std::vector<EpisodeRecord> records;
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    const auto fields = splitCsvLine(line);
    const std::string where = path + ":" + std::to_string(line_number) + ": ";
    if (fields.size() != columns.size()) {
      throw InvalidArgumentError(where + "expected " + std::to_string(columns.size()) +
                                 " columns, got " + std::to_string(fields.size()));
    }
    if (completed_column != columns.end() && fields[completed_column - columns.begin()] != "1") {
      throw InvalidArgumentError(where +
                                 "the episode was cut short (completed is not 1); run it again "
                                 "before summarising");
    }
    EpisodeRecord record;
    try {
      std::size_t used = 0;
      record.agent = fields[0];
      record.scene_set = fields[1];
      record.scene_seed = std::stoull(fields[2], &used);
      record.start_azimuth_rad = std::stod(fields[3]);
      record.max_steps = std::stoi(fields[4]);
      record.steps = std::stoi(fields[5]);
      if (fields[6] != "0" && fields[6] != "1") throw std::invalid_argument("success not 0/1");
      record.success = fields[6] == "1";
      record.final_occlusion_px = std::stod(fields[7]);
      record.wall_time_s = std::stod(fields[8]);
    } catch (const std::exception& error) {
      throw InvalidArgumentError(where + "bad value (" + error.what() + ")");
    }
    if (record.agent.empty() || record.steps < 0 || record.max_steps < 1) {
      throw InvalidArgumentError(where + "empty agent or negative steps or max_steps < 1");
    }
    records.push_back(record);
  }
  return records;
}

std::vector<AgentSummary> summarizeAgents(const std::vector<EpisodeRecord>& records) {
  std::vector<AgentSummary> summaries;
  for (const auto& agent : agentsInOrder(records)) {
    AgentSummary summary;
    summary.agent = agent;
    std::vector<double> steps;
    double wall_time_s = 0.0;
    for (const auto& record : records) {
      if (record.agent != agent) continue;
      steps.push_back(record.countedSteps());
      summary.successes += record.success ? 1 : 0;
      summary.max_steps = std::max(summary.max_steps, record.max_steps);
      wall_time_s += record.wall_time_s;
    }
    summary.episodes = static_cast<int>(steps.size());
    double sum = 0.0;
    for (const double value : steps) sum += value;
    summary.mean_steps = sum / summary.episodes;
    double sum_squares = 0.0;
    for (const double value : steps) {
      sum_squares += (value - summary.mean_steps) * (value - summary.mean_steps);
    }
    summary.sd_steps = summary.episodes > 1 ? std::sqrt(sum_squares / (summary.episodes - 1))
                                            : std::numeric_limits<double>::quiet_NaN();
    summary.mean_wall_time_s = wall_time_s / summary.episodes;
    summaries.push_back(summary);
  }
  return summaries;
}

std::vector<PairComparison> compareAgents(const std::vector<EpisodeRecord>& records,
                                          const BestOptions& options) {
  const auto agents = agentsInOrder(records);
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
        throw InvalidArgumentError("agents " + quoted(agents[i]) + " and " + quoted(agents[j]) +
                                   " share " + std::to_string(first.size()) +
                                   " scenes; paired BEST needs at least 2");
      }
      comparisons.push_back({agents[i], agents[j], runPairedBest(first, second, options)});
    }
  }
  return comparisons;
}

std::optional<PaperAgentFigures> paperAgentFigures(const std::string& agent) {
  // Table 4 of Szemenyei & Szanto 2023 (50 scenes, 3 random ShapeNet objects, azimuth 0).
  static const std::map<std::string, PaperAgentFigures> kTable4 = {
      {"random", {"Random", 31.5, 13.9}},
      {"gradient", {"Env. Grad", 20.8, 10.2}},
      {"predicted_gradient", {"Pred. Grad", 18.5, 8.2}},
      {"rl_union", {"Agent-UN", 15.9, 4.1}},
      {"rl_intersection", {"Agent-IN", 15.8, 3.8}},
  };
  const auto found = kTable4.find(agent);
  if (found == kTable4.end()) return std::nullopt;
  return found->second;
}

std::optional<PaperPairFigures> paperPairFigures(const std::string& first,
                                                 const std::string& second) {
  // Table 5 of the paper: baseline -> method, difference = baseline - method.
  static const std::map<std::pair<std::string, std::string>, PaperPairFigures> kTable5 = {
      {{"random", "gradient"}, {6.42, 14.97, 10.73, 100.0}},
      {{"random", "predicted_gradient"}, {9.15, 17.0, 12.98, 100.0}},
      {{"random", "rl_intersection"}, {11.69, 19.36, 15.58, 100.0}},
      {{"gradient", "predicted_gradient"}, {-0.21, 2.43, 1.03, 94.6}},
      {{"gradient", "rl_intersection"}, {2.11, 6.74, 4.34, 100.0}},
      {{"predicted_gradient", "rl_intersection"}, {0.05, 1.63, 0.84, 98.47}},
  };
  const auto found = kTable5.find({first, second});
  if (found == kTable5.end()) return std::nullopt;
  return found->second;
}

std::string renderSummaryMarkdown(const std::string& title, const std::string& preamble,
                                  const std::vector<AgentSummary>& agents,
                                  const std::vector<PairComparison>& comparisons) {
  std::ostringstream md;
  md << "# " << title << "\n\n";
  if (!preamble.empty()) md << preamble << "\n\n";

  md << "## Steps to an unoccluded view (Table 4 layout)\n\n"
     << "Failed episodes (no unoccluded view within the step limit) are counted with the step "
        "limit. Paper: Table 4 of Szemenyei & Szanto 2023 (50 scenes of 3 random ShapeNet objects, "
        "PyTorch3D renderer); ours are on our own scenes and renderer, so only the ordering and "
        "rough size are comparable.\n\n";
  md << "| Agent | Episodes | Successes | Success rate | Failed (counted as limit) | Mean steps "
        "| Std | Paper mean | Paper std | Wall time / episode [s] |\n"
     << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& agent : agents) {
    const auto paper = paperAgentFigures(agent.agent);
    const int failed = agent.episodes - agent.successes;
    md << "| " << agentLabel(agent.agent) << " | " << agent.episodes << " | " << agent.successes
       << " | " << fixed(100.0 * agent.successes / agent.episodes, 1) << " % | " << failed << " ("
       << agent.max_steps << ") | " << fixed(agent.mean_steps, 1) << " | "
       << fixed(agent.sd_steps, 1) << " | " << (paper ? fixed(paper->mean_steps, 1) : "-") << " | "
       << (paper ? fixed(paper->sd_steps, 1) : "-") << " | " << fixed(agent.mean_wall_time_s, 3)
       << " |\n";
  }

  if (!comparisons.empty()) {
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
      const auto paper = paperPairFigures(pair.first, pair.second);
      const std::string paper_text = paper ? "[" + fixed(paper->hdi_low, 2) + ", " +
                                                 fixed(paper->hdi_high, 2) + "], " +
                                                 fixed(paper->difference_of_means, 2) + ", " +
                                                 fixed(paper->confidence_percent, 2) + " %"
                                           : "-";
      md << "| " << agentLabel(pair.first) << " | " << agentLabel(pair.second) << " | "
         << best.pairs << " | ";
      if (best.no_variation) {
        md << "- | - | " << fixed(best.sample_mean, 2) << " | - | - | - | - | "
           << fixed(best.sample_mean, 2) << " | " << paper_text << " |\n";
        continue;
      }
      md << fixed(best.mu_hdi.low, 2) << " | " << fixed(best.mu_hdi.high, 2) << " | "
         << fixed(best.mu_mean, 2) << " | " << fixed(100.0 * best.probability_mu_positive, 2)
         << " | " << fixed(best.effect_size_mean, 2) << " | [" << fixed(best.effect_size_hdi.low, 2)
         << ", " << fixed(best.effect_size_hdi.high, 2) << "] | " << fixed(best.nu_median, 1)
         << " | " << fixed(best.sample_mean, 2) << " | " << paper_text << " |\n";
    }
    for (const auto& pair : comparisons) {
      if (pair.best.no_variation) {
        md << "\n"
           << pair.first << " vs " << pair.second << ": " << pair.best.note
           << " (BEST skipped: the model needs sd > 0).\n";
      }
    }
  }
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
