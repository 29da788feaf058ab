// The EnvironmentInterface over the simulator's ROS services (reset, step and, where offered,
// get_occlusion_gradient): agents, the evaluation and trainers run on a simulator in another
// process or on another machine, or on the camera bridge of a real camera, exactly as they run
// in process.
#pragma once

#include <ros/ros.h>

#include <string>

#include "occlusion_env/GetOcclusionGradient.h"
#include "occlusion_env/Reset.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/env/environment_interface.hpp"

namespace occlusion_env {

struct EnvironmentClientOptions {
  double service_timeout_s = 60.0;  // how long connect() waits for the services; 0 = forever
  int reset_attempts = 3;           // transport failures of one reset before it gives up
};

/// For trainers: throws InvalidArgumentError when the simulator under `ns` (its
/// `occlusion_sim/model_split` parameter) may draw test-split models; returns false (and trains
/// on) when the parameter is not there to read, e.g. behind a camera bridge.
bool requireTrainSplit(const std::string& ns);

class EnvironmentClient : public EnvironmentInterface {
 public:
  /// `node` resolves the service names (occlusion/reset, ...). Does not connect yet.
  EnvironmentClient(ros::NodeHandle node, const EnvironmentClientOptions& options = {});

  /// Waits for reset and step (up to the timeout) and opens persistent connections; notes whether
  /// the gradient service is there too. Throws EnvironmentUnavailableError on timeout. Call again
  /// after an EnvironmentUnavailableError to wait for the environment to come back.
  void connect();

  /// A reset lost in transit is retried (reconnecting) up to reset_attempts times: nothing of the
  /// episode is lost by it. Refusals throw the core's exception for the status code;
  /// EnvironmentUnavailableError when the services cannot be reached; InvalidArgumentError for an
  /// observation that cannot be read (wrong encoding or size).
  StepResult reset(std::uint64_t seed, const ResetOptions& overrides = {}) override;
  /// Not retried (a step may have been carried out): the episode is then over.
  StepResult step(const Action& action) override;

  bool hasOcclusionGradient() const override { return has_gradient_; }
  /// From the service with the simulator's default method; a refused request gives an invalid
  /// result with the reason.
  GradientResult occlusionGradient() override;
  std::string describe() const override;

 private:
  StepResult resultFor(const CameraObservation& message);

  ros::NodeHandle node_;
  EnvironmentClientOptions options_;
  std::string reset_name_, step_name_, gradient_name_;
  ros::ServiceClient reset_client_, step_client_, gradient_client_;
  bool connected_ = false;
  bool has_gradient_ = false;

  // Reused between calls so that responses are decoded into buffers of the right capacity; the
  // observation views the latest response's images.
  Reset reset_call_;
  Step step_call_;
  GetOcclusionGradient gradient_call_;
  Observation observation_;
};

}  // namespace occlusion_env
