// One held-out episode of each agent, frame by frame: rows of occlusion overlays in one PNG and
// a Markdown section.
#pragma once

#include <string>

#include "occlusion_env/report/eval_options.hpp"

namespace occlusion_env {
namespace report {

/// One episode of each agent (options.agents when two or more, else gradient and
/// predicted_escape) on one scene of the set at `scenes_path`, as rows of frames (occluded pixels
/// red, each object's outline), evenly spaced from the start view to the last. The scene: the
/// first where the first agent fails and the last succeeds, else the set's first. Returns the
/// Markdown section; the PNG goes to options.out.
std::string runStrip(const EvalOptions& options, const std::string& scenes_path);

/// The --strip mode: runStrip(options, options.strip), its section written to OUT/strip.md.
void writeStripReport(const EvalOptions& options);

}  // namespace report
}  // namespace occlusion_env
