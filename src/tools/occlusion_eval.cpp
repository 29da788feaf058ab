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
#include "occlusion_env/eval/sweep.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/report/eval_options.hpp"
#include "occlusion_env/report/evaluation_report.hpp"
#include "occlusion_env/report/landscape_report.hpp"
#include "occlusion_env/report/model_report.hpp"
#include "occlusion_env/report/scene_set_report.hpp"
#include "occlusion_env/report/strip_report.hpp"
#include "occlusion_env/report/sweep_report.hpp"
#include "occlusion_env/tools/cli_options.hpp"

using namespace occlusion_env;          // NOLINT
using namespace occlusion_env::eval;    // NOLINT
using namespace occlusion_env::report;  // NOLINT

namespace {

/// Runs the one mode `options` holds; its output goes to options.out.
int runMode(const EvalOptions& options) {
  if (options.networks) {
    std::cout << networkSection(options);
    return 0;
  }
  std::filesystem::create_directories(options.out);
  learning::setInferenceThreadsForWorkers(options.threads);
  if (!options.scenes.empty()) {
    runSceneSet(options, options.scenes);
  } else if (!options.sweep.empty()) {
    writeSweepReport(options);
  } else if (!options.landscape.empty()) {
    writeLandscapeReport(options);
  } else if (!options.strip.empty()) {
    writeStripReport(options);
  } else if (!options.summarize.empty()) {
    summarizeEpisodeCsv(options, options.summarize);
  } else {
    runFullEvaluation(options);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  EvalOptions options;
  CLI::App app(
      "Runs agents on a scene set or on the paper's start-azimuth sweep in process, writes one CSV "
      "row per (agent, scene),\nthen the BEST summary (Markdown) and the plots (PNG). Give exactly "
      "one mode.",
      "occlusion_eval");
  tools::addOptionFlags(app, evalOptionTable(), options);
  app.callback([&options] {
    try {
      options.resolve();
    } catch (const InvalidArgumentError& error) {
      throw CLI::ValidationError(error.what());
    }
  });
  return tools::parseAndRun(app, argc, argv, [&options] { return runMode(options); });
}
