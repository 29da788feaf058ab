// occlusion_eval: runs agents on a scene set or on the paper's start-azimuth sweep in process,
// writes one CSV row per (agent, scene), then the BEST summary (Markdown) and the plots (PNG).
//
//   occlusion_eval --scenes config/scenes/test_embedded.yaml [--agents random,gradient]
//   occlusion_eval --sweep two_chairs|two_tables
//   occlusion_eval --summarize OUT/test_embedded_episodes.csv   (summary and plots only)
//   occlusion_eval --all --out doc/evaluation --report EVALUATION.md   (what scripts/evaluate.sh
//                                                                       runs: EVALUATION.md)
#include <filesystem>
#include <iostream>
#include <string>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/package_paths.hpp"
#include "occlusion_env/eval/sweep.hpp"
#include "occlusion_env/report/eval_options.hpp"
#include "occlusion_env/report/evaluation_report.hpp"
#include "occlusion_env/report/landscape_report.hpp"
#include "occlusion_env/report/model_report.hpp"
#include "occlusion_env/report/scene_set_report.hpp"
#include "occlusion_env/report/strip_report.hpp"
#include "occlusion_env/report/sweep_report.hpp"
#include "occlusion_env/tools/arguments.hpp"

using namespace occlusion_env;          // NOLINT
using namespace occlusion_env::eval;    // NOLINT
using namespace occlusion_env::report;  // NOLINT

namespace {

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
                       on the embedded scene and on Sweet Home 3D models, and the evaluation
                       report (--report)
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
  --plot-script PATH   default: scripts/plot_evaluation.py of --source-dir
  --source-dir DIR     where config/scenes, models and scripts are (default: the package's share
                       directory, the source tree in a devel space; doc/INSTALL.md)
  --model PATH         the model of the agents that need one (default: each one's shipped model)
  --report FILE        with --all: the evaluation report's file, its links pointing into --out
                       (default: EVALUATION.md in --out)
)";

EvalOptions parse(int argc, char** argv) {
  EvalOptions cl;
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
  if (cl.source_dir.empty()) cl.source_dir = packageShareDirectory();
  if (cl.plot_script.empty()) cl.plot_script = cl.source_dir + "/scripts/plot_evaluation.py";
  return cl;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const EvalOptions cl = parse(argc, argv);
    if (cl.networks) {
      std::cout << networkSection(cl);
      return 0;
    }
    std::filesystem::create_directories(cl.out);
    if (!cl.scenes.empty()) {
      runSceneSet(cl, cl.scenes);
    } else if (!cl.sweep.empty()) {
      writeSweepReport(cl);
    } else if (!cl.landscape.empty()) {
      writeLandscapeReport(cl);
    } else if (!cl.strip.empty()) {
      writeStripReport(cl);
    } else if (!cl.summarize.empty()) {
      summarizeEpisodeCsv(cl, cl.summarize);
    } else {
      runFullEvaluation(cl);
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
