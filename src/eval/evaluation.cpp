#include "occlusion_env/eval/evaluation.hpp"

#include <ostream>

#include "occlusion_env/core/errors.hpp"
#include "occlusion_env/core/occlusion_gradient.hpp"

namespace occlusion_env {
namespace eval {

AgentRegistry AgentRegistry::withBuiltinAgents() {
  AgentRegistry registry;
  registry.add("random", [](Environment&) { return std::make_unique<RandomAgent>(); });
  registry.add("gradient", [](Environment& env) {
    // The gradient object lives as long as the agent's source that uses it.
    std::shared_ptr<OcclusionGradient> gradient = makeAnalyticGradient();
    OcclusionGradientSource source = [&env, gradient] { return gradient->compute(env); };
    return std::make_unique<GradientAgent>(std::move(source));
  });
  return registry;
}

void AgentRegistry::add(const std::string& name, AgentFactory factory) {
  if (name.empty() || !factory) throw InvalidArgumentError("agent registry: empty name or factory");
  if (!factories_.emplace(name, std::move(factory)).second) {
    throw InvalidArgumentError("agent registry: " + quoted(name) + " is already registered");
  }
}

std::vector<std::string> AgentRegistry::names() const {
  std::vector<std::string> names;
  for (const auto& entry : factories_) names.push_back(entry.first);
  return names;
}

std::unique_ptr<Agent> AgentRegistry::make(const std::string& name, Environment& env) const {
  const auto found = factories_.find(name);
  if (found == factories_.end()) {
    std::string known;
    for (const auto& entry : factories_) known += (known.empty() ? "" : ", ") + entry.first;
    throw InvalidArgumentError("unknown agent " + quoted(name) + " (known: " + known + ")");
  }
  return found->second(env);
}

int EvaluationPlan::episodes() const {
  const std::size_t azimuths = start_azimuths_rad.empty() ? 1 : start_azimuths_rad.size();
  return static_cast<int>(agents.size() * scenes.seeds.size() * azimuths);
}

std::vector<EpisodeRecord> runEvaluation(const EvaluationPlan& plan, const AgentRegistry& registry,
                                         std::ostream* csv, ProgressBar* progress) {
  if (plan.max_steps < 1) throw InvalidArgumentError("max_steps must be >= 1");
  for (const auto& name : plan.agents) {
    if (!registry.contains(name)) {
      std::string known;
      for (const auto& entry : registry.names()) known += (known.empty() ? "" : ", ") + entry;
      throw InvalidArgumentError("unknown agent " + quoted(name) + " (known: " + known + ")");
    }
  }
  EnvironmentOptions options = environmentOptionsFor(plan.scenes, plan.environment);
  options.max_steps = plan.max_steps;
  Environment env(options);

  const std::vector<double> azimuths = plan.start_azimuths_rad.empty()
                                           ? std::vector<double>{plan.scenes.start_azimuth_rad}
                                           : plan.start_azimuths_rad;
  if (csv) *csv << episodeCsvHeader() << "\n" << std::flush;
  std::vector<EpisodeRecord> records;
  for (const auto& agent_name : plan.agents) {
    std::unique_ptr<Agent> agent = registry.make(agent_name, env);
    for (const auto seed : plan.scenes.seeds) {
      for (const double azimuth : azimuths) {
        ResetOptions reset = resetOptionsFor(plan.scenes);
        reset.start_azimuth_rad = azimuth;
        const EpisodeResult result = runEpisode(env, *agent, seed, reset, plan.max_steps);
        EpisodeRecord record;
        record.agent = agent_name;
        record.scene_set = plan.scenes.name;
        record.scene_seed = seed;
        record.start_azimuth_rad = azimuth;
        record.max_steps = plan.max_steps;
        record.steps = result.steps;
        record.success = result.success;
        record.final_occlusion_px = static_cast<double>(result.final_occlusion_pixels);
        record.wall_time_s = result.wall_time_s;
        records.push_back(record);
        if (csv) {
          writeEpisodeCsvRow(*csv, record);
          csv->flush();
        }
        if (progress) {
          progress->update(static_cast<int>(records.size()),
                           agent_name + " seed " + std::to_string(seed) + ": " +
                               (record.success ? std::to_string(record.steps) + " steps"
                                               : std::string("failed")));
        }
      }
    }
  }
  if (progress) progress->finish();
  return records;
}

}  // namespace eval
}  // namespace occlusion_env
