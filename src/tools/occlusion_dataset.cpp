// occlusion_dataset: training data (the paper's Algorithm 1) in the BOP format, with occlusion,
// gradient and oracle labels (dataset/bop_dataset.hpp), and its audit.
//   occlusion_dataset --out data/train_embedded --scenes 1000 --frames 20
//   occlusion_dataset --audit data/train_embedded --samples 200
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>

#include "occlusion_env/dataset/generator.hpp"
#include "occlusion_env/eval/progress.hpp"
#include "occlusion_env/tools/cli_options.hpp"

namespace {

using occlusion_env::OptionSpec;
using occlusion_env::OptionTable;

/// The tool's own options; the data's come from datasetOptionTable().
struct Arguments {
  occlusion_env::dataset::DatasetOptions options;
  std::string out;    // write into this folder, or
  std::string audit;  // audit the dataset in this one
  int samples = 200;
  std::uint64_t audit_seed = 1;
};

const OptionTable<Arguments>& argumentTable() {
  static const auto table =
      OptionTable<Arguments>()
          .add("out", &Arguments::out,
               OptionSpec("the dataset folder (new, or one made with the same options)"))
          .add("audit", &Arguments::audit, OptionSpec("audit the dataset in this folder instead"))
          .add("samples", &Arguments::samples,
               OptionSpec("frames the audit checks").range(1, 10000000))
          .add("seed", &Arguments::audit_seed, OptionSpec("the audit's random draw of frames"));
  return table;
}

int audit(const Arguments& args) {
  using namespace occlusion_env;
  const dataset::AuditReport report =
      dataset::auditDataset(args.audit, args.samples, args.audit_seed);
  for (const std::string& line : report.problems) std::cerr << "audit: " << line << "\n";
  std::cout << "audit of " << args.audit << ": " << report.frames_checked << " frames checked, "
            << report.failures << " mismatches\n";
  return report.failures == 0 ? 0 : 1;
}

int generate(const Arguments& args) {
  using namespace occlusion_env;
  const dataset::DatasetOptions& options = args.options;
  std::cerr << "occlusion_dataset: " << options.scenes << " scenes x " << options.frames
            << " frames at " << options.size << " px into " << args.out
            << (options.oracle_labels ? " (with oracle labels)" : "") << "\n";
  std::unique_ptr<eval::ProgressBar> bar;
  const dataset::GenerationReport report =
      dataset::generateDataset(args.out, options, [&bar, &options](int done, int total) {
        if (!bar) bar = std::make_unique<eval::ProgressBar>(std::cerr, total, "scenes");
        bar->update(done, std::to_string(done * options.frames) + " frames");
      });
  if (bar) bar->finish();
  std::cout << "occlusion_dataset: " << report.scenes_written << " scenes written ("
            << report.frames_written << " frames), " << report.scenes_skipped
            << " complete already; " << std::fixed << std::setprecision(1) << report.seconds
            << " s, " << (report.seconds > 0 ? report.frames_written / report.seconds : 0.0)
            << " frames/s\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  Arguments args;
  CLI::App app(
      "Writes N_s scenes x N_i frames of training data in the BOP format: each scene from a "
      "training\nseed at its start view, each next frame after a random move of the camera "
      "(1..max-move-steps\nsteps of 0.05 rad in one uniformly random direction), with the "
      "occlusion mask, L, L_s, its\ngradient and descent direction, and the oracle's step count "
      "and escape direction per frame.\nOnly training seeds (< 1,000,000) and the catalogue's "
      "train-split models are used. An\ninterrupted run resumes: complete scenes are kept. The "
      "audit (--audit DIR [--samples N] [--seed S])\nre-renders random stored frames from their "
      "scene seed and pose and compares images and labels.",
      "occlusion_dataset");
  tools::addOptionFlags(app, argumentTable(), args, {"out"});
  tools::addOptionFlags(app, dataset::datasetOptionTable(), args.options);
  tools::addOptionFlags(app, argumentTable(), args, {"audit", "samples", "seed"});
  app.callback([&args] {
    if (args.out.empty() == args.audit.empty()) throw CLI::ValidationError("give --out or --audit");
  });
  return tools::parseAndRun(app, argc, argv,
                            [&args] { return args.audit.empty() ? generate(args) : audit(args); });
}
