#include "occlusion_env/report/scene_set_report.hpp"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/env/scene_setup.hpp"
#include "occlusion_env/eval/progress.hpp"
#include "occlusion_env/eval/summary.hpp"

namespace occlusion_env {
namespace report {

namespace fs = std::filesystem;
using namespace eval;  // NOLINT

std::string writeSceneSetSummary(const EvalOptions& cl, const std::vector<EpisodeRecord>& records,
                                 const std::string& name, const std::string& episodes_csv) {
  std::cerr << "occlusion_eval: paired BEST (JAGS) for every pair of agents...\n";
  const auto agents = summarizeAgents(records, agentRegistry());
  const auto comparisons = compareAgents(records, agentRegistry(), cl.best);
  const std::string prefix = (fs::path(cl.out) / name).string() + "_";
  writeComparisonCsv(comparisons, prefix + "best_pairs.csv");
  writePosteriorSamplesCsv(comparisons, prefix + "best_mu_samples.csv");

  std::ostringstream preamble;
  preamble << "Scene set `" << name << "`, " << (records.empty() ? 0 : records.front().max_steps)
           << " steps at most per episode; episodes: `"
           << fs::path(episodes_csv).filename().string() << "`. BEST: " << cl.best.chains
           << " chains x " << cl.best.samples_per_chain << " samples after "
           << cl.best.burn_in_iterations << " burn-in (JAGS, seed " << cl.best.seed << ").";
  std::string markdown =
      renderSummaryMarkdown("Evaluation: " + name, preamble.str(), agents, comparisons);
  if (cl.plots) {
    markdown += "\n![steps per agent](" + name + "_steps_boxplot.png)\n";
    if (!comparisons.empty()) {
      markdown += "\n![BEST posteriors](" + name + "_best_posteriors.png)\n";
    }
  }
  std::ofstream(prefix + "summary.md") << markdown;
  runPlots(cl, {"--prefix", name + "_", "--episodes", episodes_csv, "--posterior",
                prefix + "best_mu_samples.csv", "--comparisons", prefix + "best_pairs.csv"});
  std::cerr << "occlusion_eval: wrote " << prefix << "summary.md\n";
  return markdown;
}

std::vector<EpisodeRecord> runPlanToCsv(const EvaluationPlan& plan, const std::string& csv_path) {
  std::ofstream csv(csv_path);
  if (!csv) throw InvalidArgumentError("cannot write " + csv_path);
  ProgressBar progress(std::cerr, plan.episodes(agentRegistry()), plan.scenes.name);
  progress.update(0, "starting");
  auto records = runEvaluation(plan, agentRegistry(), &csv, &progress);
  std::cerr << "occlusion_eval: wrote " << csv_path << "\n";
  return records;
}

std::string runSceneSet(const EvalOptions& cl, const std::string& scenes_path) {
  EvaluationPlan plan;
  plan.scenes = loadSceneSet(scenes_path);
  requireDisjoint(plan.scenes, kTrainingSeedRange);
  if (cl.limit && static_cast<std::size_t>(*cl.limit) < plan.scenes.seeds.size()) {
    plan.scenes.seeds.resize(*cl.limit);
  }
  plan.agents =
      cl.agents.empty() ? agentRegistry().runnableByDefault() : cl.agents;  // the oracle too
  plan.model_path = cl.model;
  applySceneRandomization(plan.environment, cl.world, cl.depth_sensor, cl.randomize);
  plan.max_steps = cl.max_steps.value_or(50);
  const std::string csv_path = (fs::path(cl.out) / (plan.scenes.name + "_episodes.csv")).string();
  const auto records = runPlanToCsv(plan, csv_path);
  return writeSceneSetSummary(cl, records, plan.scenes.name, csv_path);
}

void summarizeEpisodeCsv(const EvalOptions& options, const std::string& episodes_csv) {
  const auto records = readEpisodeCsv(episodes_csv);
  if (records.empty()) throw InvalidArgumentError(episodes_csv + " holds no episodes");
  writeSceneSetSummary(options, records, records.front().scene_set, episodes_csv);
}

}  // namespace report
}  // namespace occlusion_env
