// The whole evaluation (occlusion_eval --all, run by scripts/evaluate.sh): the networks, the
// policies, the held-out scene sets, one episode frame by frame, a landscape and the sweeps, as
// the evaluation report (--report, else EVALUATION.md in --out).
#pragma once

#include <string>

#include "occlusion_env/report/eval_options.hpp"

namespace occlusion_env {
namespace report {

/// The --all mode: every section into options.out (CSVs, plots, the report), and with
/// options.report the report at that path, its links pointing into options.out.
void runFullEvaluation(const EvalOptions& options);

/// `markdown` with its links to files in the output folder (a bare file name ending in .png,
/// .md or .csv) prefixed by `prefix`.
std::string withLinkPrefix(const std::string& markdown, const std::string& prefix);

}  // namespace report
}  // namespace occlusion_env
