// The random agent: the paper's lower baseline.
#pragma once

#include "occlusion_env/agents/agent.hpp"
#include "occlusion_env/common/random.hpp"

namespace occlusion_env {

/// Moves in a uniformly random direction: a unit action at an angle ~ U[0, 2 pi) in the
/// (azimuth, elevation) plane, drawn from the agent's own seeded RandomSource.
class RandomAgent : public Agent {
 public:
  explicit RandomAgent(std::uint64_t seed = 0);
  void reset(std::uint64_t seed) override;
  Action act(const RigObservation& observation) override;

 private:
  RandomSource random_;
};

}  // namespace occlusion_env
