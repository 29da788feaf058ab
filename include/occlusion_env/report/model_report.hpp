// The learned models in the evaluation: the multi-task network's variants in the layout of the
// paper's Table 3 and the shipped PPO policies, read from their manifests (*.json).
#pragma once

#include <string>

#include "occlusion_env/report/eval_options.hpp"

namespace occlusion_env {
namespace report {

/// Table 3 layout (the --networks mode prints it): the variants trained by
/// scripts/train_table3.sh (options.source_dir/doc/training/*.json) beside the paper's rows, then
/// the shipped models (options.source_dir/models/*.json), each with the data it was validated on.
std::string networkSection(const EvalOptions& options);

/// The shipped PPO policies (models/*.json of kind ppo_policy): recipe, training length, the end
/// of their training curves and their validation figures; "" when there are none.
std::string policySection(const EvalOptions& options);

}  // namespace report
}  // namespace occlusion_env
