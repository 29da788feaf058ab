// Agents by name: what each needs and how to make it. The evaluation, the command-line tools, the
// agent node and the documentation take their list of agents from here; adding an agent means
// adding one entry (an AgentEntry function beside the agent, listed in core_agents.cpp or in the
// registry of the library that holds it).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "occlusion_env/agents/agent.hpp"
#include "occlusion_env/env/environment_interface.hpp"

namespace occlusion_env {

/// What an agent needs besides what a camera gives (RigObservation): each need is a way to reach
/// what no camera gives, and an agent gets only the ways its entry declares (AgentCapabilities).
struct AgentNeeds {
  bool occlusion_gradient = false;      // EnvironmentInterface::occlusionGradient(): a simulator
  bool simulation = false;              // the in-process simulation itself (reads the scene)
  bool privileged_observation = false;  // EnvironmentInterface::privilegedObservation(): the
                                        // view's masks and true occlusion (a simulator in process)
  bool model_file = false;              // a trained model (AgentCapabilities::model_path)
};

/// Where an agent is to run: what a caller gives AgentRegistry::make().
struct AgentContext {
  EnvironmentInterface& environment;  // outlives the agent
  std::string model_path;             // "" = the entry's default_model_path
};

/// The current view's gradient dL_s/d(azimuth, elevation) (doc/GRADIENT.md).
using OcclusionGradientSource = std::function<GradientResult()>;
/// The current view's privileged record (valid until the environment's next reset or step).
using PrivilegedObservationSource = std::function<PrivilegedObservation()>;

/// What the registry hands an entry's factory: the model path, and a way to reach what no camera
/// gives only for the needs the entry declares; the others stay empty. The environment itself is
/// not handed over, so an agent cannot read more than it declares.
struct AgentCapabilities {
  std::string model_path;                              // with needs.model_file: never empty
  OcclusionGradientSource occlusion_gradient;          // with needs.occlusion_gradient
  Environment* simulation = nullptr;                   // with needs.simulation; outlives the agent
  PrivilegedObservationSource privileged_observation;  // with needs.privileged_observation
};

using AgentFactory = std::function<std::unique_ptr<Agent>(const AgentCapabilities&)>;

struct AgentEntry {
  std::string name;     // lower_case, no commas or spaces
  std::string summary;  // one sentence, for --help, doc/AGENTS.md and reports
  AgentNeeds needs;
  /// false for references that read what a real camera cannot give (the oracle): they are
  /// reported beside the competitors, not as one.
  bool competes = true;
  std::string paper_label;         // the paper's name for the method ("" if it has none)
  std::string default_model_path;  // with needs.model_file: the shipped model ("" = none: the
                                   // agent runs only when named, with a model path)
  AgentFactory make;
};

class AgentRegistry {
 public:
  /// Throws InvalidArgumentError for a bad or duplicate name or an empty factory.
  void add(AgentEntry entry);

  /// nullptr when `name` is not registered.
  const AgentEntry* find(const std::string& name) const;
  /// Throws InvalidArgumentError naming the registered agents when `name` is not one.
  const AgentEntry& at(const std::string& name) const;
  /// In registration order.
  const std::vector<AgentEntry>& entries() const { return entries_; }
  std::vector<std::string> names() const;
  /// The agents an evaluation runs when none are named: all but the generic entries that need a
  /// model file and ship none (they run only when named, with a model path).
  std::vector<std::string> runnableByDefault() const;
  /// Of those, the ones with competes = true, in registration order.
  std::vector<std::string> competitors() const;

  /// Why `name` cannot run on `environment` (a need it does not meet), or "" when it can.
  std::string unmetNeed(const std::string& name, EnvironmentInterface& environment) const;

  /// Makes `name` for `context`, handing its factory the capabilities its needs declare. Throws
  /// InvalidArgumentError for an unknown name or a missing model file and InvalidStateError when
  /// the environment does not meet the agent's needs.
  std::unique_ptr<Agent> make(const std::string& name, const AgentContext& context) const;

 private:
  std::vector<AgentEntry> entries_;
};

}  // namespace occlusion_env
