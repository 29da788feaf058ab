#include "occlusion_env/report/scene_set_report.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/text_file.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/env/scene_setup.hpp"
#include "occlusion_env/env/simulated_camera_rig.hpp"
#include "occlusion_env/eval/progress.hpp"
#include "occlusion_env/eval/summary.hpp"
#include "occlusion_env/learning/occlusion_estimator.hpp"

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
  // Through the camera bridge an episode ends on the bridge's verdict: say so where it is counted.
  const bool estimated = std::any_of(records.begin(), records.end(), [](const EpisodeRecord& r) {
    return r.occlusion_source == OcclusionSource::kEstimated;
  });
  if (estimated) {
    preamble << " Through the camera bridge: a success is the bridge's verdict on its estimate, "
                "not the simulator's truth; how often the view was truly clear: `"
             << name << ".md`.";
  }
  std::string markdown =
      renderSummaryMarkdown("Evaluation: " + name, preamble.str(), agents, comparisons);
  if (cl.plots) {
    markdown += "\n![steps per agent](" + name + "_steps_boxplot.png)\n";
    if (!comparisons.empty()) {
      markdown += "\n![BEST posteriors](" + name + "_best_posteriors.png)\n";
    }
  }
  writeTextFile(prefix + "summary.md", markdown);
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

namespace {

// Through the bridge: the view where an episode ended was truly clear (the simulator's L [px]).
bool trulyClear(std::int64_t true_final_px, std::int64_t success_threshold_px) {
  return true_final_px <= success_threshold_px;
}

}  // namespace

void writeBridgeTruthCsv(const std::vector<EpisodeRecord>& records,
                         const std::vector<std::int64_t>& true_final_px,
                         std::int64_t success_threshold_px, const std::string& path) {
  if (records.size() != true_final_px.size()) {
    throw InvalidArgumentError("bridge truth: " + std::to_string(records.size()) +
                               " episodes but " + std::to_string(true_final_px.size()) +
                               " true occlusion figures");
  }
  std::ostringstream csv;
  csv << std::setprecision(9)
      << "agent,scene_seed,start_azimuth_rad,bridge_steps,bridge_says_clear,truly_clear,"
         "truth_occlusion_px,azimuth_rad,elevation_rad,end\n";
  for (std::size_t i = 0; i < records.size(); ++i) {
    const EpisodeRecord& record = records[i];
    csv << record.agent << ',' << record.scene_seed << ',' << record.start_azimuth_rad << ','
        << record.steps << ',' << record.success() << ','
        << trulyClear(true_final_px[i], success_threshold_px) << ',' << true_final_px[i] << ',';
    // Where the episode ended: the last pose of its path (empty where it has none).
    if (record.path.empty()) {
      csv << ',';
    } else {
      csv << record.path.back().azimuth_rad << ',' << record.path.back().elevation_rad;
    }
    csv << ',' << toString(record.end) << '\n';
  }
  writeTextFile(path, csv.str());
}

namespace {

/// Through the bridge, per agent: how often the bridge said clear, how often the view was truly
/// clear where the episode ended (`true_final_px`, the simulator's L), and how often they agreed.
std::string bridgeTable(const std::vector<EpisodeRecord>& records,
                        const std::vector<std::int64_t>& true_final_px,
                        std::int64_t success_threshold_px) {
  std::ostringstream table;
  table << "| agent | episodes | bridge says clear | truly clear | verdict agrees | mean steps "
           "|\n|---|---:|---:|---:|---:|---:|\n";
  for (std::size_t first = 0; first < records.size();) {
    std::size_t end = first;
    int said = 0, truly = 0, agree = 0, steps = 0;
    for (; end < records.size() && records[end].agent == records[first].agent; ++end) {
      const bool clear = trulyClear(true_final_px[end], success_threshold_px);
      said += records[end].success();
      truly += clear;
      agree += records[end].success() == clear;
      steps += records[end].countedSteps();  // failures at the limit, as everywhere
    }
    const int n = static_cast<int>(end - first);
    table << "| " << records[first].agent << " | " << n << " | " << said << " | " << truly << " | "
          << agree << " | " << static_cast<double>(steps) / n << " |\n";
    first = end;
  }
  return table.str();
}

/// The --scenes mode through the bridge (--through-bridge): OUT/<set>_bridge_episodes.csv, the
/// bridge's table in OUT/<set>_bridge.md, then the usual summary of those episodes.
std::string runThroughBridge(const EvalOptions& cl, EvaluationPlan plan) {
  plan.bridge = cl.bridge;
  // The estimate reads depth at the sphere the bridge will work on (the simulator's).
  plan.bridge.radius_m =
      BridgedSimulator::sphereRadius(environmentOptionsFor(plan.scenes, plan.environment));
  // Each worker thread loads its own networks. Loading them here first reports a missing or
  // corrupt model before any episode.
  learning::loadModel(cl.through_bridge);
  if (!cl.bridge_second_model.empty()) learning::loadModel(cl.bridge_second_model);
  plan.bridge_estimators = [first = cl.through_bridge, second = cl.bridge_second_model,
                            bridge = plan.bridge] {
    auto load = [](const std::string& path) {
      return std::make_shared<learning::LoadedModel>(learning::loadModel(path));
    };
    return learning::makeBridgeEstimator(load(first), bridge,
                                         second.empty() ? nullptr : load(second));
  };
  if (cl.agents.empty()) {  // those that need only what a camera gives
    plan.agents.clear();
    for (const std::string& name : agentRegistry().runnableByDefault()) {
      const AgentNeeds& needs = agentRegistry().at(name).needs;
      if (!needs.simulation && !needs.occlusion_gradient) plan.agents.push_back(name);
    }
  }
  const std::string name = plan.scenes.name + "_bridge";
  const std::string csv_path = (fs::path(cl.out) / (name + "_episodes.csv")).string();
  std::ofstream csv(csv_path);
  if (!csv) throw InvalidArgumentError("cannot write " + csv_path);
  ProgressBar progress(std::cerr, plan.episodes(agentRegistry()), name);
  std::vector<std::int64_t> true_final_px;
  const auto records = runEvaluation(plan, agentRegistry(), &csv, &progress, &true_final_px);
  const std::string truth_path = (fs::path(cl.out) / (name + "_truth.csv")).string();
  writeBridgeTruthCsv(records, true_final_px, plan.environment.reward.success_threshold_pixels,
                      truth_path);
  std::ostringstream markdown;
  markdown << "Scene set `" << plan.scenes.name << "` through the camera bridge's logic in front "
           << "of the simulator, network `" << cl.through_bridge << "`, "
           << plan.bridge.confirm_views << " confirming views at probability "
           << plan.bridge.occlusion_probability << " (at most "
           << plan.bridge.occlusion_threshold_px << " px)";
  if (!cl.bridge_second_model.empty()) {
    markdown << ", joined by network `" << cl.bridge_second_model << "` at probability "
             << plan.bridge.second_occlusion_probability;
  }
  markdown << "; truly clear: the simulator's L <= "
           << plan.environment.reward.success_threshold_pixels
           << " px where the episode ended (per episode: `" << name << "_truth.csv`).\n\n"
           << bridgeTable(records, true_final_px, plan.environment.reward.success_threshold_pixels);
  writeTextFile((fs::path(cl.out) / (name + ".md")).string(), markdown.str());
  std::cout << markdown.str();
  return markdown.str() + "\n" + writeSceneSetSummary(cl, records, name, csv_path);
}

}  // namespace

std::string runSceneSet(const EvalOptions& cl, const std::string& scenes_path) {
  EvaluationPlan plan;
  plan.scenes = loadSceneSet(scenes_path);
  requireDisjoint(plan.scenes, kTrainerSeedRange);
  if (cl.limit && static_cast<std::size_t>(*cl.limit) < plan.scenes.seeds.size()) {
    plan.scenes.seeds.resize(*cl.limit);
  }
  plan.agents =
      cl.agents.empty() ? agentRegistry().runnableByDefault() : cl.agents;  // the oracle too
  plan.model_path = cl.model;
  cl.applySceneRandomization(plan.environment);
  plan.max_steps = cl.max_steps.value_or(50);
  plan.threads = cl.threads;
  if (!cl.through_bridge.empty()) return runThroughBridge(cl, plan);
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
