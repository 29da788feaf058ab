// occlusion_dagger: one DAgger round's data (learning/dagger.hpp): the predicted-escape agent of
// a model rolled out on training scenes, every state it visits labelled by the oracle, written
// as a dataset occlusion_train reads beside the base data; resumable (re-run the same command).
//   occlusion_dagger --model models/multitask_unet64.pt --out data/dagger_1 --scenes 1000
//       --first-seed 100000 --source sweethome3d --category chair --category table --size 128
//   ... --world room --depth-sensor realsense_d435: the same in a room through a sensor's depth
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>

#include "occlusion_env/eval/progress.hpp"
#include "occlusion_env/learning/dagger.hpp"
#include "occlusion_env/learning/training.hpp"
#include "occlusion_env/tools/cli_options.hpp"

namespace {

using occlusion_env::OptionSpec;
using occlusion_env::OptionTable;

struct Arguments {
  occlusion_env::learning::DaggerOptions options;
  std::string out;
};

const OptionTable<Arguments>& argumentTable() {
  static const auto table = OptionTable<Arguments>().add(
      "out", &Arguments::out,
      OptionSpec("the dataset folder (new, or one made with the same options: resumed)"));
  return table;
}

int run(const Arguments& args) {
  using namespace occlusion_env;
  const learning::DaggerOptions& options = args.options;
  learning::setLibtorchThreads(1);  // one per worker: the workers are the parallelism
  std::cerr << "occlusion_dagger: " << options.scenes << " roll-outs of " << options.model
            << " (beta " << options.beta << ") at " << options.data.size << " px into " << args.out
            << "\n";
  std::unique_ptr<eval::ProgressBar> bar;
  const learning::DaggerReport report =
      learning::writeDaggerDataset(args.out, options, [&bar](int done, int total, int frames) {
        if (!bar) bar = std::make_unique<eval::ProgressBar>(std::cerr, total, "scenes");
        bar->update(done, std::to_string(frames) + " states");
      });
  if (bar) bar->finish();
  const double per_scene = report.scenes_written;
  std::cout << std::fixed << std::setprecision(1) << "occlusion_dagger: " << report.scenes_written
            << " scenes written (" << report.frames_written << " labelled states, "
            << report.expert_moves << " oracle moves executed, " << report.successes
            << " roll-outs unoccluded), " << report.scenes_skipped << " complete already; "
            << report.seconds << " s, "
            << (report.seconds > 0 ? report.frames_written / report.seconds : 0.0) << " states/s\n";
  if (report.scenes_written == 0) return 0;
  std::cout << std::setprecision(3) << "  per scene (summed over workers): roll-out "
            << report.rollout_seconds / per_scene << " s, writing "
            << report.write_seconds / per_scene << " s of which the oracle's labels "
            << report.oracle_seconds / per_scene << " s ("
            << (report.oracle_seconds > 0 ? report.frames_written / report.oracle_seconds : 0.0)
            << " oracle labels/s per worker)\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  Arguments args;
  CLI::App app(
      "DAgger data: rolls the predicted-escape agent of --model out on training scenes (seeds "
      "below\n900,000: validation and test seeds are refused; train-split models only) and "
      "labels every\nstate it visits with the oracle's escape direction and steps (lattice "
      "spacing 0.5 steps); with\nprobability --beta per step the oracle's move is executed "
      "instead. Writes a dataset in\nocclusion_dataset's format (doc/TRAINING.md, \"DAgger\") "
      "that occlusion_train --data reads\nbeside the base data. An interrupted run resumes: "
      "complete scenes are kept.",
      "occlusion_dagger");
  tools::addOptionFlags(app, argumentTable(), args);
  tools::addOptionFlags(app, learning::daggerOptionTable(), args.options);
  tools::addOptionFlags(
      app, dataset::datasetOptionTable(), args.options.data,
      {"size", "source", "catalog_paths", "categories", "num_objects", "validation_fraction",
       "world", "depth_sensor", "randomize", "max_scene_attempts"});
  app.callback([&args] {
    if (args.out.empty()) throw CLI::ValidationError("give --out");
    if (args.options.model.empty()) throw CLI::ValidationError("give --model");
  });
  return tools::parseAndRun(app, argc, argv, [&args] { return run(args); });
}
