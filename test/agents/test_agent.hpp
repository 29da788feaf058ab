// Test-only agents, registered only by tests (in process, and in test_agent_node through ROS).
// The circling agent always turns the camera towards +azimuth: adding it touches no file of the
// package, the registry's extension point at work. The truth-reading agent circles too but
// declares the privileged observation and records what it read of it.
#pragma once

#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "occlusion_env/agents/agent_registry.hpp"

namespace occlusion_env {
namespace testing_support {

class CirclingAgent : public Agent {
 public:
  void reset(std::uint64_t) override { ++episodes_; }
  Action act(const RigObservation& observation) override {
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
  entry.make = [](const AgentCapabilities&) { return std::make_unique<CirclingAgent>(); };
  return entry;
}

/// What a TruthReadingAgent read of the privileged record at one act().
struct TruthRead {
  std::int64_t occlusion_px = 0;             // the record's occlusion.total_pixels
  int occlusion_mask_pixels = 0;             // non-zero pixels of its occlusion mask
  const unsigned char* mask_data = nullptr;  // where its occlusion mask lies (no copy)
  int step_index = 0;                        // of the observation it acted on
};

class TruthReadingAgent : public CirclingAgent {
 public:
  TruthReadingAgent(PrivilegedObservationSource source, std::vector<TruthRead>& reads)
      : source_(std::move(source)), reads_(reads) {
    if (!source_) throw std::invalid_argument("truth-reading agent: no privileged observation");
  }
  Action act(const RigObservation& observation) override {
    const PrivilegedObservation truth = source_();
    reads_.push_back({truth.occlusion.total_pixels, cv::countNonZero(truth.occlusion_mask),
                      truth.occlusion_mask.data, observation.step_index});
    return CirclingAgent::act(observation);
  }

 private:
  PrivilegedObservationSource source_;
  std::vector<TruthRead>& reads_;
};

/// "test_truth_reading": a TruthReadingAgent appending to `reads` (which outlives its agents).
inline AgentEntry truthReadingAgentEntry(std::vector<TruthRead>& reads) {
  AgentEntry entry;
  entry.name = "test_truth_reading";
  entry.summary = "test-only: circles and records the privileged observation it reads";
  entry.needs.privileged_observation = true;
  entry.competes = false;
  entry.make = [&reads](const AgentCapabilities& capabilities) {
    return std::make_unique<TruthReadingAgent>(capabilities.privileged_observation, reads);
  };
  return entry;
}

}  // namespace testing_support
}  // namespace occlusion_env
