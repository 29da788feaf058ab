#include "occlusion_env/agents/agent_registry.hpp"

#include <algorithm>
#include <utility>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

void AgentRegistry::add(AgentEntry entry) {
  const bool plain_name =
      !entry.name.empty() && std::all_of(entry.name.begin(), entry.name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
      });
  if (!plain_name) {
    throw InvalidArgumentError(
        "agent registry: names are lower_case letters, digits and '_', got " + quoted(entry.name));
  }
  if (!entry.make)
    throw InvalidArgumentError("agent registry: " + quoted(entry.name) + " has no factory");
  if (find(entry.name) != nullptr) {
    throw InvalidArgumentError("agent registry: " + quoted(entry.name) + " is already registered");
  }
  entries_.push_back(std::move(entry));
}

const AgentEntry* AgentRegistry::find(const std::string& name) const {
  for (const AgentEntry& entry : entries_) {
    if (entry.name == name) return &entry;
  }
  return nullptr;
}

const AgentEntry& AgentRegistry::at(const std::string& name) const {
  if (const AgentEntry* entry = find(name)) return *entry;
  std::string known;
  for (const AgentEntry& entry : entries_) known += (known.empty() ? "" : ", ") + entry.name;
  throw InvalidArgumentError("unknown agent " + quoted(name) + " (known: " + known + ")");
}

std::vector<std::string> AgentRegistry::names() const {
  std::vector<std::string> names;
  for (const AgentEntry& entry : entries_) names.push_back(entry.name);
  return names;
}

namespace {

bool runsWithoutModelPath(const AgentEntry& entry) {
  return !entry.needs.model_file || !entry.default_model_path.empty();
}

}  // namespace

std::vector<std::string> AgentRegistry::runnableByDefault() const {
  std::vector<std::string> names;
  for (const AgentEntry& entry : entries_) {
    if (runsWithoutModelPath(entry)) names.push_back(entry.name);
  }
  return names;
}

std::vector<std::string> AgentRegistry::competitors() const {
  std::vector<std::string> names;
  for (const AgentEntry& entry : entries_) {
    if (entry.competes && runsWithoutModelPath(entry)) names.push_back(entry.name);
  }
  return names;
}

std::string AgentRegistry::unmetNeed(const std::string& name,
                                     EnvironmentInterface& environment) const {
  const AgentEntry& entry = at(name);
  if (entry.needs.occlusion_gradient && !environment.hasOcclusionGradient()) {
    return "the " + entry.name + " agent needs the simulator's occlusion gradient, which " +
           environment.describe() + " does not offer (a real camera cannot)";
  }
  if (entry.needs.simulation && environment.simulation() == nullptr) {
    return "the " + entry.name + " agent reads the scene, so it runs only on an in-process " +
           "simulator, not on " + environment.describe();
  }
  if (entry.needs.privileged_observation && !environment.hasPrivilegedObservation()) {
    return "the " + entry.name + " agent reads the privileged observation (masks, amodal " +
           "silhouettes, true occlusion), which " + environment.describe() +
           " does not offer: only an in-process simulator does (a real camera cannot)";
  }
  return "";
}

namespace {

// What `entry` may reach of `environment`: only what its needs declare.
AgentCapabilities capabilitiesFor(const AgentEntry& entry, EnvironmentInterface& environment,
                                  const std::string& model_path) {
  AgentCapabilities capabilities;
  capabilities.model_path = model_path.empty() ? entry.default_model_path : model_path;
  if (entry.needs.model_file && capabilities.model_path.empty()) {
    throw InvalidArgumentError("the " + entry.name + " agent needs a model file");
  }
  if (entry.needs.occlusion_gradient) {
    capabilities.occlusion_gradient = [&environment] { return environment.occlusionGradient(); };
  }
  if (entry.needs.simulation) capabilities.simulation = environment.simulation();
  if (entry.needs.privileged_observation) {
    capabilities.privileged_observation = [&environment] {
      return environment.privilegedObservation();
    };
  }
  return capabilities;
}

}  // namespace

std::unique_ptr<Agent> AgentRegistry::make(const std::string& name,
                                           const AgentContext& context) const {
  const AgentEntry& entry = at(name);
  const std::string unmet = unmetNeed(name, context.environment);
  if (!unmet.empty()) throw InvalidStateError(unmet);
  std::unique_ptr<Agent> agent =
      entry.make(capabilitiesFor(entry, context.environment, context.model_path));
  if (!agent) throw InvalidStateError("the factory of " + quoted(entry.name) + " made no agent");
  return agent;
}

}  // namespace occlusion_env
