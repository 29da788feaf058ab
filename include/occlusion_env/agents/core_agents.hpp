// The registry of the core's agents. Libraries with more agents (learning) offer their own
// function that starts from this one.
#pragma once

#include "occlusion_env/agents/agent_registry.hpp"

namespace occlusion_env {

/// Registry entries of the core's agents, each defined beside its agent.
AgentEntry randomAgentEntry();
AgentEntry gradientAgentEntry();

/// Every agent of the core, in the order reports list them.
AgentRegistry coreAgents();

}  // namespace occlusion_env
