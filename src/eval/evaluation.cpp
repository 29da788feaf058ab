#include "occlusion_env/eval/evaluation.hpp"

#include <ostream>
#include <stdexcept>

#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/simulated_camera_rig.hpp"

namespace occlusion_env {
namespace eval {
namespace {

std::vector<std::string> agentsOf(const EvaluationPlan& plan, const AgentRegistry& registry) {
  return plan.agents.empty() ? registry.competitors() : plan.agents;
}

}  // namespace

int EvaluationPlan::episodes(const AgentRegistry& registry) const {
  const std::size_t azimuths = start_azimuths_rad.empty() ? 1 : start_azimuths_rad.size();
  return static_cast<int>(agentsOf(*this, registry).size() * scenes.seeds.size() * azimuths);
}

std::vector<EpisodeRecord> runEvaluation(const EvaluationPlan& plan, const AgentRegistry& registry,
                                         std::ostream* csv, ProgressBar* progress,
                                         std::vector<std::int64_t>* true_final_occlusion_px) {
  if (plan.max_steps < 1) throw InvalidArgumentError("max_steps must be >= 1");
  const std::vector<std::string> agents = agentsOf(plan, registry);
  for (const auto& name : agents) registry.at(name);  // unknown names fail before any work
  EnvironmentOptions options = environmentOptionsFor(plan.scenes, plan.environment);
  options.max_steps = plan.max_steps;
  Environment simulator(options);
  std::unique_ptr<BridgedSimulator> bridged;
  if (plan.bridge_estimator) {
    bridged = std::make_unique<BridgedSimulator>(simulator, plan.bridge, plan.bridge_estimator);
  }
  EnvironmentInterface& environment =
      bridged ? static_cast<EnvironmentInterface&>(bridged->bridge()) : simulator;

  const std::vector<double> azimuths = plan.start_azimuths_rad.empty()
                                           ? std::vector<double>{plan.scenes.start_azimuth_rad}
                                           : plan.start_azimuths_rad;
  EpisodeRunOptions run_options;
  run_options.max_steps = plan.max_steps;
  if (csv) *csv << episodeCsvHeader() << "\n" << std::flush;
  std::vector<EpisodeRecord> records;
  for (const auto& agent_name : agents) {
    std::unique_ptr<Agent> agent = registry.make(agent_name, {environment, plan.model_path});
    for (const auto seed : plan.scenes.seeds) {
      for (const double azimuth : azimuths) {
        EpisodeRequest request;
        request.agent = agent_name;
        request.scene_set = plan.scenes.name;
        request.seed = seed;
        request.reset = resetOptionsFor(plan.scenes);
        request.reset.start_azimuth_rad = azimuth;
        EpisodeRecord record = runEpisode(environment, *agent, request, run_options);
        if (!record.completed()) {
          throw std::runtime_error(agent_name + " on scene " + std::to_string(seed) + ": " +
                                   record.message);
        }
        if (csv) {
          writeEpisodeCsvRow(*csv, record);
          csv->flush();
        }
        records.push_back(std::move(record));
        if (bridged && true_final_occlusion_px) {
          true_final_occlusion_px->push_back(bridged->trueOcclusion());
        }
        if (progress) {
          const EpisodeRecord& last = records.back();
          progress->update(
              static_cast<int>(records.size()),
              agent_name + " seed " + std::to_string(seed) + ": " +
                  (last.success() ? std::to_string(last.steps) + " steps" : std::string("failed")));
        }
      }
    }
  }
  if (progress) progress->finish();
  return records;
}

}  // namespace eval
}  // namespace occlusion_env
