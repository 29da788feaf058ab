// A test-only agent, registered only by tests (in process, and in test_agent_node through ROS):
// it circles the scene, always turning the camera towards +azimuth. Adding it touches no file of
// the package: this is the registry's extension point at work.
#pragma once

#include <memory>

#include "occlusion_env/agents/agent_registry.hpp"

namespace occlusion_env {
namespace testing_support {

class CirclingAgent : public Agent {
 public:
  void reset(std::uint64_t) override { ++episodes_; }
  Action act(const Observation& observation, const StepInfo&) override {
    if (observation.rgb.empty() || observation.depth.empty()) {
      throw std::invalid_argument("circling agent: no RGB-D image in the observation");
    }
    return {1.0, 0.0};
  }
  int episodes() const { return episodes_; }

 private:
  int episodes_ = 0;
};

inline AgentEntry circlingAgentEntry() {
  AgentEntry entry;
  entry.name = "test_circling";
  entry.summary = "test-only: always turns towards +azimuth";
  entry.make = [](const AgentContext&) { return std::make_unique<CirclingAgent>(); };
  return entry;
}

}  // namespace testing_support
}  // namespace occlusion_env
