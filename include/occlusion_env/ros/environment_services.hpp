// The reset and step services (occlusion/reset, occlusion/step) of any EnvironmentInterface: one
// server for the simulator node and the camera bridge (issue 27). The node says how a result
// becomes its observation message: the simulator's truth and masks, or the bridge's estimate with
// its camera frame's header.
#pragma once

#include <ros/ros.h>

#include <functional>

#include "occlusion_env/CameraObservation.h"
#include "occlusion_env/Reset.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/env/environment_interface.hpp"

namespace occlusion_env {

class EnvironmentServices {
 public:
  /// Writes the observation of a reset or step the environment accepted (step_index 0: a reset).
  /// It may throw: the response's status then says so.
  using ObservationWriter =
      std::function<void(const StepResult& result, CameraObservation& observation)>;
  /// Called after a step was answered OK, with the time the answer took [s].
  using StepAnswered = std::function<void(const StepResult& result, double answer_s)>;

  /// Advertises reset and step on `node` (served by its callback queue) for `environment`, which
  /// must outlive this object.
  EnvironmentServices(ros::NodeHandle node, EnvironmentInterface& environment,
                      ObservationWriter write_observation, StepAnswered step_answered = {});

  /// The handlers: errors go into the response's status (the core's exception types as in
  /// ros/status.hpp), and the call itself always succeeds so that the client sees it.
  bool reset(Reset::Request& request, Reset::Response& response);
  bool step(Step::Request& request, Step::Response& response);

 private:
  EnvironmentInterface& environment_;
  ObservationWriter write_observation_;
  StepAnswered step_answered_;
  ros::ServiceServer reset_service_;
  ros::ServiceServer step_service_;
};

}  // namespace occlusion_env
