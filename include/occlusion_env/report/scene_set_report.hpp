// The agents on a held-out scene set: one CSV row per (agent, scene), then the paired BEST
// summary (Markdown and CSVs) and the plots.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "occlusion_env/agents/episode.hpp"
#include "occlusion_env/eval/evaluation.hpp"
#include "occlusion_env/report/eval_options.hpp"

namespace occlusion_env {
namespace report {

/// Runs `plan` with a progress bar on stderr, each episode a row of the CSV at `csv_path`.
std::vector<EpisodeRecord> runPlanToCsv(const eval::EvaluationPlan& plan,
                                        const std::string& csv_path);

/// Summary Markdown (OUT/<name>_summary.md), BEST CSVs and plots of one scene-set run of the
/// episodes `records` (read from or written to `episodes_csv`). Returns the Markdown. Records
/// whose end was estimated (through the camera bridge) make it say that a success there is the
/// bridge's verdict and point to OUT/<name>.md for the truth.
std::string writeSceneSetSummary(const EvalOptions& options,
                                 const std::vector<EpisodeRecord>& records, const std::string& name,
                                 const std::string& episodes_csv);

/// Through the camera bridge, one CSV row per episode at `path`: the agent, the scene, where the
/// episode ended, the bridge's verdict and the simulator's truth there (`true_final_px[i]` [px]
/// for `records[i]`; truly clear at or below `success_threshold_px`). The columns of
/// scripts/bridge_evaluation.py's bridge_truth.csv, after the agent and start azimuth. Throws
/// InvalidArgumentError when the two lists differ in length or the file cannot be written.
void writeBridgeTruthCsv(const std::vector<EpisodeRecord>& records,
                         const std::vector<std::int64_t>& true_final_px,
                         std::int64_t success_threshold_px, const std::string& path);

/// The --scenes mode: the agents on the scene set at `scenes_path` (at most options.limit
/// scenes), its episodes CSV and summary in options.out. Returns the summary's Markdown.
std::string runSceneSet(const EvalOptions& options, const std::string& scenes_path);

/// The --summarize mode: the summary and plots of the episodes in the CSV of an earlier run.
void summarizeEpisodeCsv(const EvalOptions& options, const std::string& episodes_csv);

}  // namespace report
}  // namespace occlusion_env
