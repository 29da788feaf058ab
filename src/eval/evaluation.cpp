#include "occlusion_env/eval/evaluation.hpp"

#include <mutex>
#include <optional>
#include <ostream>
#include <stdexcept>

#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/workers.hpp"
#include "occlusion_env/env/simulated_camera_rig.hpp"

namespace occlusion_env {
namespace eval {
namespace {

std::vector<std::string> agentsOf(const EvaluationPlan& plan, const AgentRegistry& registry) {
  return plan.agents.empty() ? registry.competitors() : plan.agents;
}

// One episode of a plan: which agent on which scene from which start azimuth.
struct EpisodeSlot {
  std::size_t agent = 0;  // index into EvaluationRun::agents
  std::uint64_t seed = 0;
  double start_azimuth_rad = 0.0;
};

// An episode a worker finished, waiting for those before it to be handed on.
struct FinishedEpisode {
  EpisodeRecord record;
  std::int64_t true_final_px = 0;  // through the bridge: the simulator's L where it ended [px]
};

// What the workers of one evaluation share. Episodes are taken in slot order and handed on
// (CSV, records, progress) in slot order, so the output does not depend on the worker count.
struct EvaluationRun {
  EvaluationRun(const EvaluationPlan& plan, const AgentRegistry& registry)
      : plan(plan), registry(registry) {}
  const EvaluationPlan& plan;
  const AgentRegistry& registry;
  std::vector<std::string> agents;
  std::vector<EpisodeSlot> slots;  // agent-major, as a single worker runs them
  EnvironmentOptions environment_options;

  std::mutex mutex;                                      // guards everything below and the outputs
  std::vector<std::optional<FinishedEpisode>> finished;  // per slot, until handed on
  std::size_t handed_on = 0;                             // slots before this are in `records`
  std::vector<EpisodeRecord> records;
  std::ostream* csv = nullptr;
  ProgressBar* progress = nullptr;
  std::vector<std::int64_t>* true_final_px = nullptr;

  // Stores the episode of `slot` and hands on every finished episode that is next in order.
  void finish(std::size_t slot, FinishedEpisode episode) {
    const std::lock_guard<std::mutex> lock(mutex);
    finished[slot] = std::move(episode);
    for (; handed_on < slots.size() && finished[handed_on]; ++handed_on) {
      FinishedEpisode& done = *finished[handed_on];
      if (csv) {
        writeEpisodeCsvRow(*csv, done.record);
        csv->flush();
      }
      if (plan.bridge_estimators && true_final_px) true_final_px->push_back(done.true_final_px);
      records.push_back(std::move(done.record));
      finished[handed_on].reset();
      if (progress) {
        const EpisodeRecord& last = records.back();
        progress->update(
            static_cast<int>(records.size()),
            last.agent + " seed " + std::to_string(last.scene_seed) + ": " +
                (last.success() ? std::to_string(last.steps) + " steps" : std::string("failed")));
      }
    }
  }
};

// One worker: its own simulator (a GL context, made on this thread), bridge estimator and agent;
// episodes taken from `jobs` (indices into run.slots).
void work(EvaluationRun& run, JobSource& jobs) {
  Environment simulator(run.environment_options);
  std::unique_ptr<ViewOcclusionEstimator> estimator;
  std::unique_ptr<BridgedSimulator> bridged;
  if (run.plan.bridge_estimators) {
    estimator = run.plan.bridge_estimators();
    bridged = std::make_unique<BridgedSimulator>(simulator, run.plan.bridge, estimator.get());
  }
  EnvironmentInterface& environment =
      bridged ? static_cast<EnvironmentInterface&>(bridged->bridge()) : simulator;
  EpisodeRunOptions run_options;
  run_options.max_steps = run.plan.max_steps;

  std::unique_ptr<Agent> agent;  // of run.agents[agent_index]; slots are agent-major
  std::size_t agent_index = 0;
  while (const std::optional<std::size_t> slot = jobs.next()) {
    const EpisodeSlot& episode = run.slots[*slot];
    const std::string& agent_name = run.agents[episode.agent];
    if (!agent || agent_index != episode.agent) {
      agent.reset();  // the last agent's model goes before the next one's is loaded
      agent = run.registry.make(agent_name, {environment, run.plan.model_path});
      agent_index = episode.agent;
    }
    EpisodeRequest request;
    request.agent = agent_name;
    request.scene_set = run.plan.scenes.name;
    request.seed = episode.seed;
    request.reset = resetOptionsFor(run.plan.scenes);
    request.reset.start_azimuth_rad = episode.start_azimuth_rad;
    FinishedEpisode finished;
    finished.record = runEpisode(environment, *agent, request, run_options);
    if (!finished.record.completed()) {
      throw std::runtime_error(agent_name + " on scene " + std::to_string(episode.seed) + ": " +
                               finished.record.message);
    }
    if (bridged) finished.true_final_px = bridged->trueOcclusion();
    run.finish(*slot, std::move(finished));
  }
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
  if (plan.threads < 1) throw InvalidArgumentError("threads must be >= 1");
  EvaluationRun run(plan, registry);
  run.agents = agentsOf(plan, registry);
  for (const auto& name : run.agents) registry.at(name);  // unknown names fail before any work
  run.environment_options = environmentOptionsFor(plan.scenes, plan.environment);
  run.environment_options.max_steps = plan.max_steps;

  const std::vector<double> azimuths = plan.start_azimuths_rad.empty()
                                           ? std::vector<double>{plan.scenes.start_azimuth_rad}
                                           : plan.start_azimuths_rad;
  for (std::size_t agent = 0; agent < run.agents.size(); ++agent) {
    for (const auto seed : plan.scenes.seeds) {
      for (const double azimuth : azimuths) run.slots.push_back({agent, seed, azimuth});
    }
  }
  run.finished.resize(run.slots.size());
  run.csv = csv;
  run.progress = progress;
  run.true_final_px = true_final_occlusion_px;
  if (csv) *csv << episodeCsvHeader() << "\n" << std::flush;

  runWorkers(plan.threads, run.slots.size(), [&run](JobSource& jobs) { work(run, jobs); });
  if (progress) progress->finish();
  return std::move(run.records);
}

}  // namespace eval
}  // namespace occlusion_env
