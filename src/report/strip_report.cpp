#include "occlusion_env/report/strip_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/text_file.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/render/visualization.hpp"

namespace occlusion_env {
namespace report {

namespace fs = std::filesystem;

namespace {

constexpr int kFrames = 6;     // frames per agent's row
constexpr int kFramePx = 160;  // side of one tile [px]

// One agent's episode with, when kept, the occlusion overlay of each view.
struct StripRun {
  EpisodeRecord record;
  std::vector<cv::Mat> frames;
};

// The agents of the strip on one environment, made once and reused on every scene tried.
struct StripEpisodes {
  const SceneSet& set;
  const std::vector<std::string>& agents;
  int max_steps;
  Environment& env;
  std::vector<std::unique_ptr<Agent>> made;
  cv::Rect view;  // where the objects are in any kept frame: every tile shows this square

  // Each agent's episode on scene `seed`; with `keep_frames` its overlays are kept and `view`
  // grows to the objects in them.
  std::vector<StripRun> runOn(std::uint64_t seed, bool keep_frames) {
    std::vector<StripRun> runs(agents.size());
    for (std::size_t a = 0; a < agents.size(); ++a) {
      EpisodeRequest request;
      request.agent = agents[a];
      request.scene_set = set.name;
      request.seed = seed;
      request.reset = resetOptionsFor(set);
      EpisodeRunOptions run_options;
      run_options.max_steps = max_steps;
      if (keep_frames) {
        run_options.on_result = [this, &runs, a](const StepResult& result) {
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
  }
};

// The square around `objects`, a tenth and 8 px larger, inside the image.
cv::Rect squareAround(const cv::Rect& objects, int image_width, int image_height) {
  const int side = std::max(objects.width, objects.height) * 11 / 10 + 8;
  const cv::Point centre(objects.x + objects.width / 2, objects.y + objects.height / 2);
  const cv::Rect image(0, 0, image_width, image_height);
  return cv::Rect(centre.x - side / 2, centre.y - side / 2, side, side) & image;
}

// One row of up to kFrames tiles of `view`, evenly spaced over the run's frames and labelled;
// white tiles fill a short row.
cv::Mat stripRow(const StripRun& run, const std::string& agent, const cv::Rect& view) {
  const auto& frames = run.frames;
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
    const std::string label = agent + " t=" + std::to_string(t);
    cv::putText(tile, label, {4, 14}, cv::FONT_HERSHEY_SIMPLEX, 0.4, {255, 255, 255}, 1,
                cv::LINE_AA);
    tiles.push_back(tile);
  }
  while (static_cast<int>(tiles.size()) < kFrames) {
    tiles.push_back(cv::Mat(kFramePx, kFramePx, CV_8UC3, cv::Scalar(255, 255, 255)));
  }
  cv::Mat row;
  cv::hconcat(tiles, row);
  return row;
}

std::string stripMarkdown(const SceneSet& set, std::uint64_t seed,
                          const std::vector<std::string>& agents, const std::vector<StripRun>& runs,
                          const std::string& png) {
  std::ostringstream md;
  md << "## One held-out episode, frame by frame\n\n"
     << "Scene " << seed << " of `" << set.name
     << "` (the first of the set where the first agent fails and the last succeeds), from the "
        "same start view: each row is one agent's episode, "
     << kFrames
     << " frames evenly spaced from the start view (t = 0) to the last; occluded pixels red, "
        "each object's full outline in its colour.";
  for (const StripRun& run : runs) {
    md << " " << run.record.agent << ": "
       << (run.record.success()
               ? std::to_string(run.record.steps) + " steps, unoccluded."
               : "still occluded after " + std::to_string(run.record.steps) + " steps.");
  }
  md << "\n\n![" << agents.front() << " and " << agents.back() << ", frame by frame](" << png
     << ")\n";
  return md.str();
}

}  // namespace

std::string runStrip(const EvalOptions& cl, const std::string& scenes_path) {
  const SceneSet set = loadSceneSet(scenes_path);
  requireDisjoint(set, kTrainerSeedRange);
  if (set.seeds.empty()) throw InvalidArgumentError(scenes_path + ": no seeds");
  const std::vector<std::string> agents =
      cl.agents.size() >= 2 ? cl.agents : std::vector<std::string>{"gradient", "predicted_escape"};
  const int max_steps = cl.max_steps.value_or(50);
  EnvironmentOptions options = environmentOptionsFor(set);
  options.max_steps = max_steps;
  Environment env(options);
  StripEpisodes episodes{set, agents, max_steps, env, {}, {}};
  for (const auto& name : agents) {
    episodes.made.push_back(agentRegistry().make(name, {env, cl.model}));
  }

  std::uint64_t seed = set.seeds.front();
  for (const std::uint64_t candidate : set.seeds) {
    const std::vector<StripRun> runs = episodes.runOn(candidate, false);
    if (!runs.front().record.success() && runs.back().record.success()) {
      seed = candidate;
      break;
    }
  }
  const std::vector<StripRun> runs = episodes.runOn(seed, true);
  const cv::Rect view = squareAround(episodes.view, options.width, options.height);
  std::vector<cv::Mat> rows;
  for (std::size_t a = 0; a < runs.size(); ++a) rows.push_back(stripRow(runs[a], agents[a], view));
  cv::Mat strip;
  cv::vconcat(rows, strip);
  const std::string png = set.name + "_strip_" + std::to_string(seed) + ".png";
  if (!cv::imwrite((fs::path(cl.out) / png).string(), strip)) {
    throw std::runtime_error("cannot write " + (fs::path(cl.out) / png).string());
  }
  return stripMarkdown(set, seed, agents, runs, png);
}

void writeStripReport(const EvalOptions& options) {
  const std::string markdown = runStrip(options, options.strip);
  writeTextFile((fs::path(options.out) / "strip.md").string(), markdown);
}

}  // namespace report
}  // namespace occlusion_env
