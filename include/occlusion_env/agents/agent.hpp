// An agent chooses camera moves from what the camera sees. It knows nothing of where its
// observations come from: an in-process simulator, the simulator's ROS services or a real camera
// (env/environment_interface.hpp). It is given only what a camera on a rig gives
// (RigObservation); what no camera gives (masks, true occlusion, the simulator's gradient, the
// scene) reaches only the reference agents whose registry entry declares the need, through what
// the registry hands their factory (agents/agent_registry.hpp, doc/AGENTS.md).
#pragma once

#include <cstdint>

#include "occlusion_env/env/environment_interface.hpp"

namespace occlusion_env {

class Agent {
 public:
  virtual ~Agent() = default;
  /// Starts a new episode; `seed` fixes the agent's own random draws.
  virtual void reset(std::uint64_t seed) = 0;
  /// The next move, given what the camera sees now. Throws (any std::exception) when the
  /// observation is not one it can act on; the episode runner then cuts the episode short.
  virtual Action act(const RigObservation& observation) = 0;
};

}  // namespace occlusion_env
