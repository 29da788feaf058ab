// occlusion_dataset: training data (the paper's Algorithm 1) in the BOP format, with occlusion,
// gradient and oracle labels (dataset/bop_dataset.hpp), and its audit.
//   occlusion_dataset --out data/train_embedded --scenes 1000 --frames 20
//   occlusion_dataset --audit data/train_embedded --samples 200
#include <iomanip>
#include <iostream>
#include <string>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/dataset/generator.hpp"
#include "occlusion_env/eval/progress.hpp"
#include "occlusion_env/tools/arguments.hpp"

namespace {

constexpr const char* kUsage = R"(Usage: occlusion_dataset --out DIR [options]
       occlusion_dataset --audit DIR [--samples N] [--seed S]
Writes N_s scenes x N_i frames of training data in the BOP format: each scene from a training
seed at its start view, each next frame after a random move of the camera (1..max-move-steps
steps of 0.05 rad in one uniformly random direction), with the occlusion mask, L, L_s, its
gradient and descent direction, and the oracle's step count and escape direction per frame.
Only training seeds (< 1,000,000) and the catalogue's train-split models are used. An
interrupted run resumes: complete scenes are kept. The audit re-renders random stored frames
from their scene seed and pose and compares images and labels.

Options:
  --out DIR              the dataset folder (new, or one made with the same options)
  --scenes N             number of scenes (default 1000)
  --frames N             frames per scene (default 20, the paper's)
  --first-seed S         scene seeds S .. S + N - 1 (default 0)
  --size N               image width and height [px] (default 128)
  --source S             embedded | sweethome3d | folder (default embedded)
  --path P               a .sh3f file or folder (sweethome3d), the root (folder); repeatable
  --category C           draw objects of this category only; repeatable
  --objects N            objects per scene (default 3)
  --max-move-steps N     longest move between frames, in steps (default 4)
  --no-oracle            leave out the oracle labels (much faster)
  --validation F         fraction of whole scenes for validation (default 0.2)
  --threads N            worker threads, one environment each (default 2)
  --audit DIR            audit the dataset in DIR instead
  --samples N            frames the audit checks (default 200)
  --seed S               the audit's random draw of frames (default 1)
  --help                 this text
)";

// Checks `samples` frames of the dataset in `dir` against fresh renders; 1 on any mismatch.
int runAudit(const std::string& dir, int samples, std::uint64_t seed) {
  using namespace occlusion_env;
  const dataset::AuditReport report = dataset::auditDataset(dir, samples, seed);
  for (const std::string& line : report.problems) std::cerr << "audit: " << line << "\n";
  std::cout << "audit of " << dir << ": " << report.frames_checked << " frames checked, "
            << report.failures << " mismatches\n";
  return report.failures == 0 ? 0 : 1;
}

// Generates (or resumes) the dataset in `out` with a progress bar.
int runGeneration(const occlusion_env::dataset::DatasetOptions& options, const std::string& out) {
  using namespace occlusion_env;
  std::cerr << "occlusion_dataset: " << options.scenes << " scenes x " << options.frames
            << " frames at " << options.size << " px into " << out
            << (options.oracle_labels ? " (with oracle labels)" : "") << "\n";
  std::unique_ptr<eval::ProgressBar> bar;
  const dataset::GenerationReport report =
      dataset::generateDataset(out, options, [&bar, &options](int done, int total) {
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
  dataset::DatasetOptions options;
  std::string out, audit;
  int samples = 200;
  std::uint64_t audit_seed = 1;
  try {
    tools::ArgumentReader reader(argc, argv);
    while (reader.next()) {
      const std::string& flag = reader.flag();
      if (flag == "--help" || flag == "-h") {
        std::cout << kUsage;
        return 0;
      } else if (flag == "--out") {
        out = reader.text();
      } else if (flag == "--scenes") {
        options.scenes = static_cast<int>(reader.integer(1, 1000000));
      } else if (flag == "--frames") {
        options.frames = static_cast<int>(reader.integer(1, 100000));
      } else if (flag == "--first-seed") {
        options.first_seed = reader.unsignedInteger();
      } else if (flag == "--size") {
        options.size = static_cast<int>(reader.integer(64, 1024));
      } else if (flag == "--source") {
        options.source = reader.text();
      } else if (flag == "--path") {
        options.catalog_paths.push_back(reader.text());
      } else if (flag == "--category") {
        options.categories.push_back(reader.text());
      } else if (flag == "--objects") {
        options.num_objects = static_cast<int>(reader.integer(2, 8));
      } else if (flag == "--max-move-steps") {
        options.max_move_steps = static_cast<int>(reader.integer(1, 100));
      } else if (flag == "--no-oracle") {
        options.oracle_labels = false;
      } else if (flag == "--validation") {
        options.validation_fraction = reader.number(0.0, 0.5);
      } else if (flag == "--threads") {
        options.threads = static_cast<int>(reader.integer(1, 64));
      } else if (flag == "--audit") {
        audit = reader.text();
      } else if (flag == "--samples") {
        samples = static_cast<int>(reader.integer(1, 10000000));
      } else if (flag == "--seed") {
        audit_seed = reader.unsignedInteger();
      } else {
        reader.unknown();
      }
    }
    if (out.empty() == audit.empty()) throw tools::ArgumentError("give --out or --audit");
  } catch (const tools::ArgumentError& error) {
    std::cerr << "occlusion_dataset: " << error.what() << "\n" << kUsage;
    return 2;
  }
  try {
    return audit.empty() ? runGeneration(options, out) : runAudit(audit, samples, audit_seed);
  } catch (const std::exception& error) {
    std::cerr << "occlusion_dataset: " << error.what() << "\n";
    return 1;
  }
}
