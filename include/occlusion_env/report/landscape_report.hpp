// One scene from above: the total occlusion L over a grid of camera angles around the paths the
// agents took on it (CSV, plot, Markdown).
#pragma once

#include <string>

#include "occlusion_env/report/eval_options.hpp"

namespace occlusion_env {
namespace report {

/// Each agent's episode on the first scene of the set at `scenes_path`, and L over a grid of
/// camera angles around their paths (CSVs and plot in options.out). Returns the Markdown section.
std::string runLandscape(const EvalOptions& options, const std::string& scenes_path);

/// The --landscape mode: runLandscape(options, options.landscape), its section written to
/// OUT/landscape.md.
void writeLandscapeReport(const EvalOptions& options);

}  // namespace report
}  // namespace occlusion_env
