#include "occlusion_env/report/sweep_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <utility>
#include <vector>

#include "occlusion_env/common/text_file.hpp"
#include "occlusion_env/eval/evaluation.hpp"
#include "occlusion_env/eval/summary.hpp"
#include "occlusion_env/eval/sweep.hpp"
#include "occlusion_env/report/scene_set_report.hpp"

namespace occlusion_env {
namespace report {

namespace fs = std::filesystem;
using namespace eval;  // NOLINT

namespace {

// The sweep's episode of `agent` on scene `seed` from `azimuth`; nullptr when not run.
const EpisodeRecord* findSweepEpisode(const std::vector<EpisodeRecord>& records,
                                      const std::string& agent, std::uint64_t seed,
                                      double azimuth) {
  for (const EpisodeRecord& record : records) {
    if (record.agent == agent && record.scene_seed == seed && record.start_azimuth_rad == azimuth) {
      return &record;
    }
  }
  return nullptr;
}

// A table cell: the steps of a successful episode, `F` for a failed one.
std::string sweepCell(const EpisodeRecord* record) {
  if (!record) return "-";
  return record->success() ? std::to_string(record->steps) : "F";
}

// Steps per agent and start azimuth; with several models each cell lists them in model order.
void writeSweepStepsTable(std::ostream& md, const EvaluationPlan& plan,
                          const std::vector<std::string>& agents,
                          const std::vector<EpisodeRecord>& records) {
  md << "| Start azimuth [deg] |";
  for (const auto& agent : agents) md << " " << agent << " |";
  md << "\n|---:|";
  for (std::size_t i = 0; i < agents.size(); ++i) md << "---:|";
  md << "\n";
  for (const double azimuth : plan.start_azimuths_rad) {
    md << "| " << std::fixed << std::setprecision(2) << azimuth * 180.0 / M_PI << " |";
    for (const auto& agent : agents) {
      md << " ";
      for (std::size_t k = 0; k < plan.scenes.seeds.size(); ++k) {
        md << (k ? " / " : "")
           << sweepCell(findSweepEpisode(records, agent, plan.scenes.seeds[k], azimuth));
      }
      md << " |";
    }
    md << "\n";
  }
}

// "12.3" (the mean of counted steps), with " (2 F)" when some of the episodes failed.
std::string meanStepsCell(const std::vector<EpisodeRecord>& episodes) {
  const EpisodeStatistics statistics = summarizeEpisodes(episodes);
  std::ostringstream cell;
  cell << std::fixed << std::setprecision(1) << statistics.mean_steps;
  const int failed = statistics.completed - statistics.successes;
  if (failed > 0) cell << " (" << failed << " F)";
  return cell.str();
}

// The section of a sweep on several models: the models, each agent's mean per model, the steps
// per start azimuth (one number per model in each cell) and the plot.
std::string severalModelsSweepMarkdown(const EvalOptions& cl, const std::string& preset,
                                       const SweepScenes& scenes, const EvaluationPlan& plan,
                                       const std::vector<std::string>& agents,
                                       const std::vector<EpisodeRecord>& records) {
  const std::size_t count = scenes.models.size();
  std::ostringstream md;
  md << "## Start-azimuth sweep: " << preset << ", " << count << " " << plan.scenes.source
     << " models (Figure 5 layout)\n\n"
     << count << " scenes (preset " << preset << ", source " << plan.scenes.source
     << "), each two copies of one model: the seeds from " << kSweepSeed
     << " up that draw a model no earlier seed drew, the same one at every start azimuth. Start "
        "azimuth over [-pi/32, pi/32) in steps of pi/208, "
     << plan.max_steps << " steps at most; `F` = failed within the limit.";
  if (!scenes.skipped.empty()) {
    md << " Seeds left out:";
    for (std::size_t k = 0; k < scenes.skipped.size(); ++k) {
      md << (k ? ";" : "") << " " << scenes.skipped[k].seed << " (" << scenes.skipped[k].reason
         << ")";
    }
    md << ".";
  }
  const std::string models_csv = plan.scenes.name + "_models.csv";
  md << " The models (licences in [" << models_csv << "](" << models_csv
     << "); split: the catalogue's train/test split, the learned agents were trained on train "
        "models only):\n\n"
     << "| Model | Seed | Name | Catalogue id | Split | Width x depth x height [m] | Creator "
        "|\n|---:|---:|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < count; ++k) {
    const SweepModel& model = scenes.models[k];
    const Eigen::Vector3f& size = model.object.dimensions_m;
    md << "| " << k + 1 << " | " << model.seed << " | " << model.object.name << " | `"
       << model.object.id << "` | " << model.split << " | " << std::fixed << std::setprecision(2)
       << size.x() << " x " << size.y() << " x " << size.z() << " | " << model.object.creator
       << " |\n";
  }

  md << "\nMean steps over the " << plan.start_azimuths_rad.size()
     << " start azimuths per model (failures counted as the limit; `(n F)`: n failed)";
  if (std::find(agents.begin(), agents.end(), "oracle") != agents.end()) {
    md << "; the oracle, a reference that renders other poses, gives the floor (its lattice "
          "search bounds the fewest steps from above: an agent may beat it by a step)";
  }
  md << ":\n\n";
  md << "| Agent |";
  for (std::size_t k = 0; k < count; ++k) md << " Model " << k + 1 << " |";
  md << " All models |\n|---|";
  for (std::size_t k = 0; k <= count; ++k) md << "---:|";
  md << "\n";
  for (const auto& agent : agents) {
    md << "| " << agent << " |";
    std::vector<EpisodeRecord> all_models;
    for (const std::uint64_t seed : plan.scenes.seeds) {
      std::vector<EpisodeRecord> episodes;
      for (const EpisodeRecord& record : records) {
        if (record.agent == agent && record.scene_seed == seed) episodes.push_back(record);
      }
      md << " " << meanStepsCell(episodes) << " |";
      all_models.insert(all_models.end(), episodes.begin(), episodes.end());
    }
    md << " " << meanStepsCell(all_models) << " |\n";
  }

  md << "\nSteps per start azimuth, models 1";
  for (std::size_t k = 1; k < count; ++k) md << " / " << k + 1;
  md << " in each cell:\n\n";
  writeSweepStepsTable(md, plan, agents, records);
  if (cl.plots) {
    md << "\nOne panel per model (log scale; a cross marks a failure at the limit) and the mean "
          "over the models:\n\n![sweep "
       << preset << ", " << plan.scenes.source << " models](" << plan.scenes.name << ".png)\n";
  }
  return md.str();
}

// The section of a sweep on one model: a small table beside the plot, steps per agent and start
// azimuth.
std::string oneModelSweepMarkdown(const EvalOptions& cl, const std::string& preset,
                                  const SweepScenes& scenes, const EvaluationPlan& plan,
                                  const std::vector<EpisodeRecord>& records) {
  const std::vector<std::string>& agents = plan.agents;
  std::ostringstream md;
  md << "## Start-azimuth sweep: " << preset << " (Figure 5 layout)\n\n"
     << "One scene (preset " << preset << ", source " << plan.scenes.source << ", seed "
     << plan.scenes.seeds.front() << "), start azimuth over [-pi/32, pi/32) in steps of pi/208, "
     << plan.max_steps << " steps at most; `F` = failed within the limit.";
  const SweepModel& model = scenes.models.front();
  if (!model.redrawn.empty()) {
    // Say which rows are another model's: per other model, the start azimuths showing it.
    md << " The scene shows " << model.object.name << " (`" << model.object.id
       << "`) from most start azimuths; from others its start view is unoccluded, so the "
          "environment redraws the scene, and those rows are another model's:";
    std::vector<std::pair<ObjectInfo, std::vector<double>>> others;
    for (const auto& [azimuth, other] : model.redrawn) {
      auto entry = std::find_if(others.begin(), others.end(),
                                [&](const auto& e) { return e.first.id == other.id; });
      if (entry == others.end()) entry = others.insert(others.end(), {other, {}});
      entry->second.push_back(azimuth);
    }
    for (std::size_t k = 0; k < others.size(); ++k) {
      md << (k ? ";" : "") << " " << others[k].first.name << " (`" << others[k].first.id
         << "`) from";
      for (std::size_t i = 0; i < others[k].second.size(); ++i) {
        md << (i ? ", " : " ") << std::fixed << std::setprecision(2)
           << others[k].second[i] * 180.0 / M_PI;
      }
      md << " deg";
    }
    md << ".";
  }
  md << "\n\n";
  writeSweepStepsTable(md, plan, agents, records);
  if (cl.plots) md << "\n![sweep " << preset << "](" << plan.scenes.name << ".png)\n";
  return md.str();
}

}  // namespace

std::string runSweep(const EvalOptions& cl, const std::string& preset) {
  const int models = cl.sweep_models.value_or(defaultSweepModels(cl.sweep_source));
  std::cerr << "occlusion_eval: choosing " << models << " " << preset << " model(s) of source "
            << cl.sweep_source << "...\n";
  const SweepScenes scenes = sweepScenes(preset, cl.sweep_source, models);
  EvaluationPlan plan;
  plan.scenes = scenes.set;
  plan.start_azimuths_rad = sweepStartAzimuths();
  plan.agents =
      cl.agents.empty() ? agentRegistry().runnableByDefault() : cl.agents;  // the oracle too
  plan.model_path = cl.model;
  plan.max_steps = cl.max_steps.value_or(kSweepMaxSteps);
  plan.threads = cl.threads;
  const std::string stem = (fs::path(cl.out) / plan.scenes.name).string();
  writeSweepModelsCsv(scenes.models, stem + "_models.csv");
  const auto records = runPlanToCsv(plan, stem + ".csv");
  runPlots(cl, {"--sweep", stem + ".csv"});
  if (scenes.models.size() > 1) {
    return severalModelsSweepMarkdown(cl, preset, scenes, plan, plan.agents, records);
  }
  return oneModelSweepMarkdown(cl, preset, scenes, plan, records);
}

void writeSweepReport(const EvalOptions& options) {
  const std::string markdown = runSweep(options, options.sweep);
  writeTextFile(
      (fs::path(options.out) / (sweepSetName(options.sweep, options.sweep_source) + ".md"))
          .string(),
      markdown);
}

}  // namespace report
}  // namespace occlusion_env
