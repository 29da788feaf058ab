// occlusion_eval: runs agents on a scene set or on the paper's start-azimuth sweep in process,
// writes one CSV row per (agent, scene), then the BEST summary (Markdown) and the plots (PNG).
//
//   occlusion_eval --scenes config/scenes/test_embedded.yaml [--agents random,gradient]
//   occlusion_eval --sweep two_chairs|two_tables
//   occlusion_eval --summarize OUT/test_embedded_episodes.csv   (summary and plots only)
//   occlusion_eval --all --out doc/evaluation --report EVALUATION.md   (what scripts/evaluate.sh
//                                                                       runs: EVALUATION.md)
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/eval/best.hpp"
#include "occlusion_env/eval/evaluation.hpp"
#include "occlusion_env/eval/landscape.hpp"
#include "occlusion_env/eval/progress.hpp"
#include "occlusion_env/eval/subprocess.hpp"
#include "occlusion_env/eval/summary.hpp"
#include "occlusion_env/eval/sweep.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/render/visualization.hpp"
#include "occlusion_env/tools/arguments.hpp"

namespace fs = std::filesystem;
using namespace occlusion_env;        // NOLINT
using namespace occlusion_env::eval;  // NOLINT

namespace {

// Every agent this tool knows.
const AgentRegistry& registry() {
  static const AgentRegistry agents = learning::learningAgents();
  return agents;
}

constexpr const char* kUsage = R"(usage: occlusion_eval MODE [options]
modes (one):
  --scenes FILE        run the agents on a scene set (config/scenes/*.yaml)
  --sweep PRESET       start-azimuth sweep of two_chairs | two_tables (Figure 5)
  --summarize CSV      summary and plots from an episode CSV of an earlier run
  --landscape FILE     occlusion L over the camera angles of the set's first scene, with each
                       agent's path on it (CSV and plot)
  --strip FILE         frames of one episode of each agent (default gradient, predicted_escape)
                       on a scene of the set, side by side (PNG): the first scene where the
                       first agent fails and the last succeeds, else the set's first scene
  --networks           print the Table 3 layout (doc/training/*.json and models/*.json of the
                       source tree, beside the paper's rows) and exit
  --all                the held-out scene sets (config/scenes/test_*.yaml) and both sweeps,
                       on the embedded scene and on Sweet Home 3D models, with RESULTS.md in
                       --out (and the --report document)
options:
  --agents A,B,...     agents by name (default: every agent of the registry that runs without a
                       model path, the oracle included; --all's embedded sweeps: the competing
                       agents, as first published)
  --max-steps N        step limit per episode (default 50; 2000 for --sweep)
  --limit N            only the first N scenes of the set
  --sweep-source SRC   object source of the sweep's preset scenes (default embedded)
  --sweep-models N     models (one scene seed each) per sweep (default 1 for embedded, 6 for
                       other sources; --all: the embedded scene and N Sweet Home 3D models)
  --out DIR            output folder (default evaluation)
  --best-seed S        seed of the BEST chains (default 20130601)
  --best-samples N     kept MCMC samples per chain (default 10000; 3 chains)
  --no-plots           skip the PNGs
  --plot-script PATH   default: scripts/plot_evaluation.py of the source tree
  --source-dir DIR     where config/scenes and scripts are (default: the build's source tree)
  --model PATH         the model of the agents that need one (default: each one's shipped model)
  --report FILE        with --all: also write the evaluation report (EVALUATION.md) to FILE,
                       its links pointing into --out
)";

struct CommandLine {
  std::string scenes;
  std::string sweep;
  std::string summarize;
  std::string landscape;
  std::string strip;
  bool networks = false;
  bool all = false;
  std::vector<std::string> agents;  // empty: the registry's competitors
  int max_steps = -1;               // -1: the mode's default
  int limit = -1;
  std::string sweep_source = "embedded";
  int sweep_models = -1;  // -1: defaultSweepModels(sweep_source)
  std::string out = "evaluation";
  BestOptions best;
  bool plots = true;
  std::string source_dir = OCCLUSION_ENV_SOURCE_DIR;
  std::string plot_script;
  std::string report;
  std::string model;
};

CommandLine parse(int argc, char** argv) {
  CommandLine cl;
  tools::ArgumentReader args(argc, argv);
  while (args.next()) {
    const std::string& arg = args.flag();
    if (arg == "--scenes") {
      cl.scenes = args.text();
    } else if (arg == "--sweep") {
      cl.sweep = args.text();
    } else if (arg == "--summarize") {
      cl.summarize = args.text();
    } else if (arg == "--landscape") {
      cl.landscape = args.text();
    } else if (arg == "--strip") {
      cl.strip = args.text();
    } else if (arg == "--networks") {
      cl.networks = true;
    } else if (arg == "--all") {
      cl.all = true;
    } else if (arg == "--agents") {
      cl.agents = args.list();
      if (cl.agents.empty()) throw InvalidArgumentError("--agents: no agent named");
    } else if (arg == "--max-steps") {
      cl.max_steps = static_cast<int>(args.integer(1, 1000000));
    } else if (arg == "--limit") {
      cl.limit = static_cast<int>(args.integer(1, 1000000));
    } else if (arg == "--sweep-source") {
      cl.sweep_source = args.text();
    } else if (arg == "--sweep-models") {
      cl.sweep_models = static_cast<int>(args.integer(1, kSweepSeedSearch));
    } else if (arg == "--out") {
      cl.out = args.text();
    } else if (arg == "--best-seed") {
      cl.best.seed = args.unsignedInteger();
    } else if (arg == "--best-samples") {
      cl.best.samples_per_chain = static_cast<int>(args.integer(1, 100000000));
    } else if (arg == "--no-plots") {
      cl.plots = false;
    } else if (arg == "--model") {
      cl.model = args.text();
    } else if (arg == "--plot-script") {
      cl.plot_script = args.text();
    } else if (arg == "--source-dir") {
      cl.source_dir = args.text();
    } else if (arg == "--report") {
      cl.report = args.text();
    } else if (arg == "-h" || arg == "--help") {
      std::cout << kUsage;
      std::exit(0);
    } else {
      args.unknown();
    }
  }
  const int modes = !cl.scenes.empty() + !cl.sweep.empty() + !cl.summarize.empty() +
                    !cl.landscape.empty() + !cl.strip.empty() + cl.networks + cl.all;
  if (modes != 1) {
    throw InvalidArgumentError(
        "give exactly one of --scenes, --sweep, --summarize, --landscape, --strip, --networks, "
        "--all");
  }
  if (!cl.report.empty() && !cl.all) throw InvalidArgumentError("--report needs --all");
  if (cl.plot_script.empty()) cl.plot_script = cl.source_dir + "/scripts/plot_evaluation.py";
  return cl;
}

void runPlots(const CommandLine& cl, std::vector<std::string> plot_args) {
  if (!cl.plots) return;
  std::vector<std::string> argv = {"/usr/bin/python3", cl.plot_script, "--out", cl.out};
  argv.insert(argv.end(), plot_args.begin(), plot_args.end());
  const int status = runProgram(argv, "", "");
  if (status != 0) {
    std::cerr << "occlusion_eval: plotting failed (status " << status
              << "); is python3-matplotlib installed? (scripts/install_deps.sh)\n";
  }
}

// Summary Markdown, BEST CSVs and plots of one scene-set run. Returns the Markdown.
std::string summarize(const CommandLine& cl, const std::vector<EpisodeRecord>& records,
                      const std::string& name, const std::string& episodes_csv) {
  std::cerr << "occlusion_eval: paired BEST (JAGS) for every pair of agents...\n";
  const auto agents = summarizeAgents(records, registry());
  const auto comparisons = compareAgents(records, registry(), cl.best);
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

std::vector<EpisodeRecord> runPlan(const CommandLine& cl, const EvaluationPlan& plan,
                                   const std::string& csv_path) {
  std::ofstream csv(csv_path);
  if (!csv) throw InvalidArgumentError("cannot write " + csv_path);
  ProgressBar progress(std::cerr, plan.episodes(registry()), plan.scenes.name);
  progress.update(0, "starting");
  auto records = runEvaluation(plan, registry(), &csv, &progress);
  std::cerr << "occlusion_eval: wrote " << csv_path << "\n";
  return records;
}

std::string runSceneSet(const CommandLine& cl, const std::string& scenes_path) {
  EvaluationPlan plan;
  plan.scenes = loadSceneSet(scenes_path);
  requireDisjoint(plan.scenes, kTrainingSeedRange);
  if (cl.limit > 0 && static_cast<std::size_t>(cl.limit) < plan.scenes.seeds.size()) {
    plan.scenes.seeds.resize(cl.limit);
  }
  plan.agents = cl.agents.empty() ? registry().runnableByDefault() : cl.agents;  // the oracle too
  plan.model_path = cl.model;
  plan.max_steps = cl.max_steps > 0 ? cl.max_steps : 50;
  const std::string csv_path = (fs::path(cl.out) / (plan.scenes.name + "_episodes.csv")).string();
  const auto records = runPlan(cl, plan, csv_path);
  return summarize(cl, records, plan.scenes.name, csv_path);
}

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
std::string severalModelsSweepMarkdown(const CommandLine& cl, const std::string& preset,
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

// Runs the start-azimuth sweep of `preset` on --sweep-source with --sweep-models models.
// Returns the Markdown section; CSVs (episodes, models) and the plot go to --out.
std::string runSweep(const CommandLine& cl, const std::string& preset) {
  const int models = cl.sweep_models > 0 ? cl.sweep_models : defaultSweepModels(cl.sweep_source);
  std::cerr << "occlusion_eval: choosing " << models << " " << preset << " model(s) of source "
            << cl.sweep_source << "...\n";
  const SweepScenes scenes = sweepScenes(preset, cl.sweep_source, models);
  EvaluationPlan plan;
  plan.scenes = scenes.set;
  plan.start_azimuths_rad = sweepStartAzimuths();
  plan.agents = cl.agents.empty() ? registry().runnableByDefault() : cl.agents;  // the oracle too
  plan.model_path = cl.model;
  plan.max_steps = cl.max_steps > 0 ? cl.max_steps : kSweepMaxSteps;
  const std::string stem = (fs::path(cl.out) / plan.scenes.name).string();
  writeSweepModelsCsv(scenes.models, stem + "_models.csv");
  const auto records = runPlan(cl, plan, stem + ".csv");
  runPlots(cl, {"--sweep", stem + ".csv"});
  const std::vector<std::string>& agents = plan.agents;
  if (scenes.models.size() > 1) {
    return severalModelsSweepMarkdown(cl, preset, scenes, plan, agents, records);
  }

  // One model: a small table beside the plot, steps per agent and start azimuth.
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

// Each agent's episode on the set's first scene, and L over a grid of camera angles around their
// paths (CSV, plot). Returns the Markdown section.
std::string runLandscape(const CommandLine& cl, const std::string& scenes_path) {
  const SceneSet set = loadSceneSet(scenes_path);
  if (set.seeds.empty()) throw InvalidArgumentError(scenes_path + ": no seeds");
  const std::uint64_t seed = set.seeds.front();
  const int max_steps = cl.max_steps > 0 ? cl.max_steps : 50;
  Environment env(environmentOptionsFor(set));
  std::vector<EpisodeRecord> paths;
  EpisodeRunOptions run_options;
  run_options.max_steps = max_steps;
  for (const std::string& name : cl.agents.empty() ? registry().runnableByDefault() : cl.agents) {
    const std::unique_ptr<Agent> agent = registry().make(name, {env, cl.model});
    EpisodeRequest request;
    request.agent = name;
    request.scene_set = set.name;
    request.seed = seed;
    request.reset = resetOptionsFor(set);
    paths.push_back(runEpisode(env, *agent, request, run_options));
    if (!paths.back().completed()) throw std::runtime_error(name + ": " + paths.back().message);
  }
  env.reset(seed, resetOptionsFor(set));
  const LandscapeGrid grid = gridAround(paths, /*margin_rad=*/0.15, /*min_half_width_rad=*/0.6,
                                        /*spacing_rad=*/0.025, env.camera().elevationLimit());
  const std::string stem = set.name + "_landscape_" + std::to_string(seed);
  const std::string landscape_csv = (fs::path(cl.out) / (stem + ".csv")).string();
  const std::string paths_csv = (fs::path(cl.out) / (stem + "_paths.csv")).string();
  std::cerr << "occlusion_eval: occlusion landscape of scene " << seed << "...\n";
  const int poses = writeOcclusionLandscapeCsv(env, grid, landscape_csv);
  writeEpisodePathsCsv(paths, paths_csv);
  std::cerr << "occlusion_eval: wrote " << landscape_csv << " (" << poses << " views)\n";
  runPlots(cl, {"--landscape", landscape_csv, "--paths", paths_csv});

  std::ostringstream md;
  md << "## One scene from above: occlusion over the camera angles\n\n"
     << "Scene " << seed << " of `" << set.name << "`: the total occlusion L [px] seen from "
     << poses << " camera poses on a " << grid.spacing_rad
     << " rad grid around the start view (dark: none; the cyan line is the border between occluded "
        "and "
        "unoccluded views, L = 0 being the goal), and the path each agent took from the start "
        "(circle) to its last "
        "view (star: unoccluded; cross: still occluded after "
     << max_steps << " steps).";
  for (const EpisodeRecord& path : paths) {
    md << " " << path.agent << ": " << path.steps << " steps, "
       << (path.success() ? "unoccluded." : "failed.");
  }
  md << "\n\n";
  if (cl.plots) md << "![occlusion landscape](" << stem << ".png)\n";
  return md.str();
}

// The evaluation report's fixed text: what was run and how to read it. The numbers follow it.
std::string reportIntroduction(const CommandLine& cl) {
  std::ostringstream text;
  text << "# Evaluation: occlusion-avoiding agents\n\n"
       << "Generated from scratch by one command, from the repository root after `make build`:\n\n"
       << "    scripts/evaluate.sh\n\n"
       << "which runs `occlusion_eval --all --out doc/evaluation --report EVALUATION.md` "
          "(tables, CSVs and plots in [doc/evaluation/](doc/evaluation/)). Do not edit this file "
          "by hand: re-run the command.\n\n"
       << "**Agents** (from the agent registry, `include/occlusion_env/agents/`):";
  for (const AgentEntry& entry : registry().entries()) {
    text << " `" << entry.name << "`"
         << (entry.paper_label.empty() ? "" : " (the paper's " + entry.paper_label + ")") << ": "
         << entry.summary << ".";
  }
  text << " Each move turns the camera by 0.05 rad on its sphere (r = 4 m, 60 deg field of view, "
          "256 x 256 px). Agents are seeded with the scene seed: a run is reproducible.\n\n"
       << "**Scenes.** The held-out scene sets `config/scenes/test_embedded.yaml` (our embedded "
          "meshes), `config/scenes/test_sweethome3d.yaml` (Debian's Sweet Home 3D chairs and "
          "tables, any model) and `config/scenes/test_sweethome3d_unseen.yaml` (the same kind of "
          "scenes drawn only from the catalogue's test split: models no learned agent is trained "
          "on): 50 scenes of 3 objects each, start azimuth 0, elevation 0, at most "
       << (cl.max_steps > 0 ? cl.max_steps : 50)
       << " steps, as in the paper's Table 4. Their seeds lie at or above 1,000,000; training "
          "must use seeds below (the tool refuses test sets that reach into that range). Every "
          "agent sees the same scenes. Success: no two amodal silhouettes overlap (L = 0 px); a "
          "failed episode counts with the step limit, and the tables say how many there were.\n\n"
       << "**Statistics.** Kruschke's BEST (2013) on the paired per-scene differences of "
          "counted steps, run by JAGS: a t likelihood with normality parameter nu, Kruschke's "
          "broad priors, 3 chains. With many episodes at the step limit the differences are "
          "bimodal and nu is small; mu then follows the bulk of the differences, so the sample "
          "mean difference is shown beside it.\n\n"
       << "**Through ROS.** The same episodes run through the simulator and agent nodes, "
          "e.g. `roslaunch occlusion_env agent.launch agent:=gradient "
          "scene_set:=$(rospack find occlusion_env)/config/scenes/test_embedded.yaml csv:=/tmp/"
          "gradient.csv`, give bit-identical episodes (test/ros/agents.test checks this); "
          "`occlusion_eval --summarize` summarises such a CSV (put both agents' rows in one "
          "file for the paired comparison).\n\n"
       << "**Reading the figures.** The paper's figures come from other scenes (ShapeNet) and "
          "another renderer (PyTorch3D): compare orderings and rough sizes, not digits. The "
          "paper does not say how its random directions were drawn nor how it counted failed "
          "episodes; where our random agent needs more steps than the paper's, most of its "
          "episodes hit the step limit here. The sweeps reseed each agent with the scene seed at "
          "every start azimuth, so the random agent draws the same directions throughout a sweep "
          "(common random numbers): its curve moves in steps rather than scattering.\n\n";
  return text.str();
}

// `markdown` with its links to files in the output folder prefixed by `prefix`.
std::string withLinkPrefix(const std::string& markdown, const std::string& prefix) {
  static const std::regex kLocalLink(R"(\]\(([^)/:]+\.(png|md|csv))\))");
  return std::regex_replace(markdown, kLocalLink, "](" + prefix + "$1)");
}

// One episode of each agent on one scene of the set, as rows of frames (the occlusion overlay:
// occluded pixels red, each object's outline), up to kFrames per row evenly spaced from the
// start view to the last. The scene: the first where the first agent fails and the last
// succeeds, else the set's first. Returns the Markdown section; the PNG goes to --out.
std::string runStrip(const CommandLine& cl, const std::string& scenes_path) {
  constexpr int kFrames = 6;
  constexpr int kFramePx = 160;
  const SceneSet set = loadSceneSet(scenes_path);
  requireDisjoint(set, kTrainingSeedRange);
  if (set.seeds.empty()) throw InvalidArgumentError(scenes_path + ": no seeds");
  const std::vector<std::string> agents =
      cl.agents.size() >= 2 ? cl.agents : std::vector<std::string>{"gradient", "predicted_escape"};
  const int max_steps = cl.max_steps > 0 ? cl.max_steps : 50;
  EnvironmentOptions options = environmentOptionsFor(set);
  options.max_steps = max_steps;
  Environment env(options);
  std::vector<std::unique_ptr<Agent>> made;
  for (const auto& name : agents) made.push_back(registry().make(name, {env, cl.model}));

  struct Run {
    EpisodeRecord record;
    std::vector<cv::Mat> frames;  // overlays, one per view
  };
  cv::Rect view;  // where the objects are in any frame: every tile shows this square
  const auto runOn = [&](std::uint64_t seed, bool keep_frames) {
    std::vector<Run> runs(agents.size());
    for (std::size_t a = 0; a < agents.size(); ++a) {
      EpisodeRequest request;
      request.agent = agents[a];
      request.scene_set = set.name;
      request.seed = seed;
      request.reset = resetOptionsFor(set);
      EpisodeRunOptions run_options;
      run_options.max_steps = max_steps;
      if (keep_frames) {
        run_options.on_result = [&, a](const StepResult& result) {
          const Observation& o = *result.observation;
          runs[a].frames.push_back(occlusionOverlay(o.rgb, o.amodal_bits, o.occlusion_mask,
                                                    static_cast<int>(env.scene().objects.size())));
          const cv::Rect objects = cv::boundingRect(o.amodal_bits);
          if (objects.area() > 0) view = view.area() > 0 ? (view | objects) : objects;
        };
      }
      runs[a].record = runEpisode(env, *made[a], request, run_options);
      if (!runs[a].record.completed()) {
        throw std::runtime_error(agents[a] + ": " + runs[a].record.message);
      }
    }
    return runs;
  };
  std::uint64_t seed = set.seeds.front();
  for (const std::uint64_t candidate : set.seeds) {
    const std::vector<Run> runs = runOn(candidate, false);
    if (!runs.front().record.success() && runs.back().record.success()) {
      seed = candidate;
      break;
    }
  }
  const std::vector<Run> runs = runOn(seed, true);
  {
    const int side = std::max(view.width, view.height) * 11 / 10 + 8;
    const cv::Point centre(view.x + view.width / 2, view.y + view.height / 2);
    const cv::Rect image(0, 0, options.width, options.height);
    view = cv::Rect(centre.x - side / 2, centre.y - side / 2, side, side) & image;
  }

  std::vector<cv::Mat> rows;
  for (std::size_t a = 0; a < runs.size(); ++a) {
    const auto& frames = runs[a].frames;
    std::vector<cv::Mat> tiles;
    const int count = std::min<int>(kFrames, static_cast<int>(frames.size()));
    for (int k = 0; k < count; ++k) {
      const int t =
          count == 1
              ? 0
              : static_cast<int>(std::lround(double(k) * (frames.size() - 1) / double(count - 1)));
      cv::Mat tile;
      cv::resize(frames[t](view), tile, cv::Size(kFramePx, kFramePx), 0, 0, cv::INTER_AREA);
      cv::cvtColor(tile, tile, cv::COLOR_RGB2BGR);
      const std::string label = agents[a] + " t=" + std::to_string(t);
      cv::putText(tile, label, {4, 14}, cv::FONT_HERSHEY_SIMPLEX, 0.4, {255, 255, 255}, 1,
                  cv::LINE_AA);
      tiles.push_back(tile);
    }
    while (static_cast<int>(tiles.size()) < kFrames) {
      tiles.push_back(cv::Mat(kFramePx, kFramePx, CV_8UC3, cv::Scalar(255, 255, 255)));
    }
    cv::Mat row;
    cv::hconcat(tiles, row);
    rows.push_back(row);
  }
  cv::Mat strip;
  cv::vconcat(rows, strip);
  const std::string png = set.name + "_strip_" + std::to_string(seed) + ".png";
  if (!cv::imwrite((fs::path(cl.out) / png).string(), strip)) {
    throw std::runtime_error("cannot write " + (fs::path(cl.out) / png).string());
  }
  std::ostringstream md;
  md << "## One held-out episode, frame by frame\n\n"
     << "Scene " << seed << " of `" << set.name
     << "` (the first of the set where the first agent fails and the last succeeds), from the "
        "same start view: each row is one agent's episode, "
     << kFrames
     << " frames evenly spaced from the start view (t = 0) to the last; occluded pixels red, "
        "each object's full outline in its colour.";
  for (const Run& run : runs) {
    md << " " << run.record.agent << ": "
       << (run.record.success()
               ? std::to_string(run.record.steps) + " steps, unoccluded."
               : "still occluded after " + std::to_string(run.record.steps) + " steps.");
  }
  md << "\n\n![" << agents.front() << " and " << agents.back() << ", frame by frame](" << png
     << ")\n";
  return md.str();
}

// The manifests of the shipped models (models/*.json) of `kind` ("multitask_unet" for those
// written before kinds existed) that carry validation figures, in file-name order; unreadable
// files are left out.
// The manifests (*.json) of kind `kind` in `folder`, in file-name order.
std::vector<nlohmann::json> manifestsIn(const fs::path& folder, const std::string& kind) {
  std::vector<fs::path> paths;
  if (fs::is_directory(folder)) {
    for (const auto& entry : fs::directory_iterator(folder)) {
      if (entry.path().extension() == ".json") paths.push_back(entry.path());
    }
  }
  std::sort(paths.begin(), paths.end());
  std::vector<nlohmann::json> manifests;
  for (const fs::path& path : paths) {
    std::ifstream in(path);
    try {
      nlohmann::json manifest = nlohmann::json::parse(in);
      if (manifest.value("kind", "multitask_unet") == kind && manifest.contains("validation")) {
        manifest["manifest_file"] = path.filename().string();
        manifests.push_back(std::move(manifest));
      }
    } catch (const std::exception&) {
    }
  }
  return manifests;
}

std::vector<nlohmann::json> shippedManifests(const CommandLine& cl, const std::string& kind) {
  return manifestsIn(fs::path(cl.source_dir) / "models", kind);
}

// The shipped PPO policies (models/*.json of kind ppo_policy): recipe, training length, the end
// of their training curves and their validation figures.
std::string policySection(const CommandLine& cl) {
  const std::vector<nlohmann::json> policies = shippedManifests(cl, "ppo_policy");
  if (policies.empty()) return "";
  std::ostringstream md;
  md << "## The PPO policies (Figure 3)\n\n"
     << "The shipped policies (`models/`, trained by `occlusion_train_ppo` on training scenes "
        "and train-split models only; commands and checksums in `models/MANIFEST.md`). Training "
        "end: the means of the last episodes of training (sampled actions, random start "
        "azimuths). Validation: the mean action on 50 validation scenes (Sweet Home 3D chairs "
        "and tables of the train split, seeds 900000-900049, start azimuth 0). Training curves "
        "(the paper's Figure 3): [doc/images/ppo_training.png](doc/images/ppo_training.png), "
        "made by `scripts/plot_ppo.py` from the runs' `training_episodes.csv`.\n\n"
     << "| Policy | Reward | Actor start | Rig inputs | Env steps | Training end: steps | "
        "success | Validation: steps | success |\n|---|---|---|---|---:|---:|---:|---:|---:|\n";
  for (const nlohmann::json& m : policies) {
    const nlohmann::json& t = m.at("trained_with");
    const nlohmann::json& end = m.at("training_end");
    const nlohmann::json& v = m.at("validation");
    md << std::fixed << "| `" << fs::path(m.value("file", "?")).stem().string() << "` | "
       << t.value("reward", "?") << " | "
       << (t.value("actor_from_escape", false) ? "escape head" : "scratch") << " | "
       << (t.at("policy").value("rig_inputs", false) ? "yes" : "no") << " | "
       << m.value("env_steps", 0) << " | " << std::setprecision(1) << end.value("mean_steps", 0.0)
       << " | " << std::setprecision(0) << 100.0 * end.value("success_rate", 0.0) << " % | "
       << std::setprecision(1) << v.value("mean_steps", 0.0) << " +/- " << v.value("std_steps", 0.0)
       << " | " << std::setprecision(0) << 100.0 * v.value("success_rate", 0.0) << " % |\n";
  }
  md << "\n";
  return md.str();
}

// One row of the network table: a model's best-epoch validation figures (its manifest).
void networkRow(std::ostringstream& md, const std::string& name, const nlohmann::json& manifest) {
  const nlohmann::json& v = manifest["validation"];
  const nlohmann::json& net = manifest["network"];
  const nlohmann::json training = manifest.value("training", nlohmann::json::object());
  const nlohmann::json run = manifest.value("run", nlohmann::json::object());
  const std::string loss = training.value("direction_loss", "mse");
  // The validation's direction figure is the training's direction loss: SmoothL1 for -L1 runs.
  const std::string loss_note = loss == "smooth_l1" ? " (SmoothL1)" : "";
  md << std::fixed << "| " << name << " | " << net.value("variant", "?")
     << (loss == "smooth_l1" ? "-L1" : "")
     << (training.value("bce_weight", 0.0) > 0.0 ? " +BCE" : "") << " | "
     << net.value("input_size", 0) << " | ";
  // A warm restart (--init-from) continues the epochs and minutes of the run it started from.
  const nlohmann::json start = manifest.value("initialised_from", nlohmann::json::object());
  const std::string before =
      start.contains("epoch")
          ? std::to_string(start.value("epochs_before", start.value("epoch", 0))) + "+"
          : "";
  md << before << manifest.value("epoch", 0) << " / " << before << training.value("epochs", 0)
     << " | ";
  const nlohmann::json start_run = start.value("run", nlohmann::json::object());
  if (run.contains("minutes") && start_run.contains("minutes")) {
    md << std::setprecision(0) << start_run.value("minutes", 0.0) << "+"
       << run.value("minutes", 0.0) << " min | ";
  } else if (run.contains("minutes")) {
    md << std::setprecision(0) << run.value("minutes", 0.0) << " min | ";
  } else {
    md << "- | ";
  }
  md << std::setprecision(3) << v.value("val_dice_loss", 0.0) << " | " << std::setprecision(2)
     << 100.0 * v.value("val_pixel_accuracy", 0.0) << " % | " << 100.0 * v.value("val_iou", 0.0)
     << " % | " << std::setprecision(3) << v.value("val_gradient_mse", 0.0) << loss_note << " | "
     << std::setprecision(1) << v.value("val_gradient_angle_deg", 0.0) << " deg | "
     << std::setprecision(3) << v.value("val_escape_mse", 0.0) << loss_note << " | "
     << std::setprecision(1) << v.value("val_escape_angle_deg", 0.0) << " deg |\n";
}

// Table 3 layout: the variants trained by scripts/train_table3.sh (doc/training/*.json) and
// the shipped models (models/*.json), beside the paper's rows.
std::string networkSection(const CommandLine& cl) {
  std::ostringstream md;
  md << "## The multi-task network (Table 3 layout)\n\n"
     << "Validation figures (the epoch with the best validation IoU) on the validation scenes "
        "of the dataset (`data/train_sweethome3d`: 1000 Sweet Home 3D scenes of train-split "
        "chairs and tables, 20 frames each; whole scenes held out for validation: 16,000 "
        "training and 4,000 validation frames), at the network's resolution. The rows from "
        "`doc/training/` were trained by `scripts/train_table3.sh` (their commands in their "
        "manifests there, with logs and curves; every run's IoU per epoch: "
        "[doc/training/iou_per_epoch.png](doc/training/iou_per_epoch.png)): the five variants "
        "under the paper's loss on the same data, at the same resolution, for the same number "
        "of epochs, one thread each, one run each; a name with `_bce<X>` adds X times a "
        "pixel-wise cross-entropy to the loss, a further tag more training scenes (the "
        "manifest lists the datasets; the validation frames are the same). The shipped models: "
        "the commands in `models/MANIFEST.md`. Training = the run's wall time. "
        "Epoch = best / of; a+b: a warm restart, b more epochs (a new cosine schedule) from "
        "weights trained for a epochs (`--init-from`; the minutes of the runs before first). "
        "Dice = soft Dice loss 1 - (2 sum(p t) + 1) / (sum(p^2) + sum(t^2) + 1), mean over "
        "images (Eq. 10); IoU (of the occlusion class, over all validation "
        "pixels) and pixel accuracy of the occlusion map thresholded at 0.5; MSE = "
        "||prediction - (sin, cos)||^2 (Eq. 11; for -L1 rows the SmoothL1 loss, beta 0.01, they "
        "were trained with); angle = mean angular error of the normalised "
        "prediction (gradient: the descent direction of the simulator's gradient; escape: the "
        "oracle's direction of escape).\n\n"
        "The paper's rows: 256 px ShapeNet images (130,000 with its validation split), 50 epochs, "
        "its own gradient labels. Its Dice column is not comparable: the authors' loss "
        "(`loss.py`) is 1 - (sum(p t) + 1) / (sum(p^2) + sum(t^2) + 1), without the factor 2, "
        "so a perfect map scores 0.5 there; its IoU is the same occlusion-class IoU, averaged "
        "over batches of 128.\n\n"
     << "| Model | Variant | Size | Epoch | Training | Dice | Pixel acc | IoU | Gradient MSE | "
        "Gradient angle | Escape MSE | Escape angle "
        "|\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  // The trained variants in the paper's order, each resolution together.
  std::vector<nlohmann::json> runs =
      manifestsIn(fs::path(cl.source_dir) / "doc" / "training", "multitask_unet");
  const auto rank = [](const nlohmann::json& m) {
    const std::string loss =
        m.value("training", nlohmann::json::object()).value("direction_loss", "mse");
    const std::vector<std::string> order = {"unet", "r_unet", "sr_unet", "sar_unet"};
    const std::string variant = m.at("network").value("variant", "");
    const auto at = std::find(order.begin(), order.end(), variant) - order.begin();
    return std::make_pair(m.at("network").value("input_size", 0),
                          2 * static_cast<int>(at) + (loss == "smooth_l1" ? 1 : 0));
  };
  std::stable_sort(runs.begin(), runs.end(), [&](const nlohmann::json& a, const nlohmann::json& b) {
    return rank(a) < rank(b);
  });
  for (const nlohmann::json& manifest : runs) {
    if (!manifest.contains("network")) continue;
    const std::string file = manifest.value("manifest_file", "?");
    networkRow(md,
               "[" + fs::path(file).stem().string() + "](doc/training/" +
                   fs::path(file).stem().string() + ".png)",
               manifest);
  }
  for (const nlohmann::json& manifest : shippedManifests(cl, "multitask_unet")) {
    if (!manifest.contains("network")) continue;
    networkRow(md, "shipped `" + fs::path(manifest.value("file", "?")).stem().string() + "`",
               manifest);
  }
  md << "| paper: Base UNet | unet | 256 | - / 50 | - | (0.607) | 99.65 % | 61.09 % | 0.038 | - | "
        "- "
        "| - |\n"
     << "| paper: R-UNet | r_unet | 256 | - / 50 | - | (0.606) | 99.65 % | 61.47 % | 0.038 | - | - "
        "| "
        "- |\n"
     << "| paper: SR-UNet | sr_unet | 256 | - / 50 | - | (0.610) | 99.64 % | 60.34 % | 0.038 | - | "
        "- "
        "| - |\n"
     << "| paper: SAR-UNet | sar_unet | 256 | - / 50 | - | (0.609) | 99.66 % | 61.87 % | 0.038 | - "
        "| "
        "- | - |\n"
     << "| paper: SAR-UNet-L1 | sar_unet-L1 | 256 | - / 50 | - | (0.604) | 99.67 % | 62.37 % | "
        "0.005 "
        "| - | - | - |\n\n";
  return md.str();
}

void runAll(const CommandLine& cl) {
  std::string sections = networkSection(cl) + policySection(cl);
  for (const char* set : {"test_embedded", "test_sweethome3d", "test_sweethome3d_unseen"}) {
    const std::string summary = runSceneSet(cl, cl.source_dir + "/config/scenes/" + set + ".yaml");
    // The scene set's own heading, one level down.
    sections += "## Held-out scene set `" + std::string(set) + "`\n" +
                summary.substr(summary.find('\n') + 1) + "\n";
  }
  sections += runStrip(cl, cl.source_dir + "/config/scenes/test_sweethome3d.yaml") + "\n";
  sections += runLandscape(cl, cl.source_dir + "/config/scenes/test_embedded.yaml") + "\n";
  // The embedded scene (the sweeps as first published), then several Sweet Home 3D models.
  for (const char* source : {"embedded", "sweethome3d"}) {
    for (const char* preset : {"two_chairs", "two_tables"}) {
      CommandLine sweep_cl = cl;
      sweep_cl.max_steps = cl.max_steps > 0 && cl.max_steps != 50 ? cl.max_steps : -1;
      sweep_cl.sweep_source = source;
      if (sweep_cl.sweep_source == "embedded") {
        // As first published: its one scene, the competing agents.
        sweep_cl.sweep_models = -1;
        if (sweep_cl.agents.empty()) sweep_cl.agents = registry().competitors();
      }
      sections += runSweep(sweep_cl, preset) + "\n";
    }
  }
  // Headings below the sections' own "##": one level down.
  sections = std::regex_replace(sections, std::regex("\n## (Steps|Paired)"), "\n### $1");

  const fs::path results = fs::path(cl.out) / "RESULTS.md";
  std::ofstream(results) << "# Evaluation results\n\nGenerated by `occlusion_eval --all`.\n\n"
                         << sections;
  std::cerr << "occlusion_eval: wrote " << results.string() << "\n";
  if (!cl.report.empty()) {
    const fs::path report = fs::absolute(cl.report);
    const std::string prefix =
        fs::relative(fs::absolute(cl.out), report.parent_path()).generic_string() + "/";
    std::ofstream out(report);
    if (!out) throw InvalidArgumentError("cannot write " + report.string());
    out << reportIntroduction(cl) << withLinkPrefix(sections, prefix);
    std::cerr << "occlusion_eval: wrote " << report.string() << "\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const CommandLine cl = parse(argc, argv);
    if (cl.networks) {
      std::cout << networkSection(cl);
      return 0;
    }
    fs::create_directories(cl.out);
    if (!cl.scenes.empty()) {
      runSceneSet(cl, cl.scenes);
    } else if (!cl.sweep.empty()) {
      const std::string markdown = runSweep(cl, cl.sweep);
      std::ofstream(fs::path(cl.out) / (sweepSetName(cl.sweep, cl.sweep_source) + ".md"))
          << markdown;
    } else if (!cl.landscape.empty()) {
      const std::string markdown = runLandscape(cl, cl.landscape);
      std::ofstream(fs::path(cl.out) / "landscape.md") << markdown;
    } else if (!cl.strip.empty()) {
      const std::string markdown = runStrip(cl, cl.strip);
      std::ofstream(fs::path(cl.out) / "strip.md") << markdown;
    } else if (!cl.summarize.empty()) {
      const auto records = readEpisodeCsv(cl.summarize);
      if (records.empty()) throw InvalidArgumentError(cl.summarize + " holds no episodes");
      summarize(cl, records, records.front().scene_set, cl.summarize);
    } else {
      runAll(cl);
    }
  } catch (const tools::ArgumentError& error) {
    std::cerr << "occlusion_eval: " << error.what() << "\n" << kUsage;
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "occlusion_eval: " << error.what() << "\n" << kUsage;
    return 1;
  }
  return 0;
}
