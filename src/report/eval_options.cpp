// The one translation unit of the report library that sees libtorch (the learned agents).
#include "occlusion_env/report/eval_options.hpp"

#include <iostream>
#include <string>
#include <vector>

#include "occlusion_env/eval/subprocess.hpp"
#include "occlusion_env/learning/learned_agents.hpp"

namespace occlusion_env {
namespace report {

const AgentRegistry& agentRegistry() {
  static const AgentRegistry agents = learning::learningAgents();
  return agents;
}

void runPlots(const EvalOptions& cl, std::vector<std::string> plot_args) {
  if (!cl.plots) return;
  std::vector<std::string> argv = {"/usr/bin/python3", cl.plot_script, "--out", cl.out};
  argv.insert(argv.end(), plot_args.begin(), plot_args.end());
  const int status = eval::runProgram(argv, "", "");
  if (status != 0) {
    std::cerr << "occlusion_eval: plotting failed (status " << status
              << "); is python3-matplotlib installed? (scripts/install_deps.sh)\n";
  }
}

}  // namespace report
}  // namespace occlusion_env
