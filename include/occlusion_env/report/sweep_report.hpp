// The paper's start-azimuth sweep (Figure 5): the agents on the preset scene of one or several
// models from each start azimuth, as CSVs, a plot and a Markdown section.
#pragma once

#include <string>

#include "occlusion_env/report/eval_options.hpp"

namespace occlusion_env {
namespace report {

/// Runs the sweep of `preset` (two_chairs | two_tables) on options.sweep_source with
/// options.sweep_models models. Returns the Markdown section; the CSVs (episodes, models) and the
/// plot go to options.out.
std::string runSweep(const EvalOptions& options, const std::string& preset);

/// The --sweep mode: runSweep(options, options.sweep), its section written to
/// OUT/<sweep set name>.md.
void writeSweepReport(const EvalOptions& options);

}  // namespace report
}  // namespace occlusion_env
