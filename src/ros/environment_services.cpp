#include "occlusion_env/ros/environment_services.hpp"

#include <chrono>
#include <utility>

#include "occlusion_env/ros/msg_conversion.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/status.hpp"

namespace occlusion_env {

EnvironmentServices::EnvironmentServices(ros::NodeHandle node, EnvironmentInterface& environment,
                                         ObservationWriter write_observation,
                                         StepAnswered step_answered)
    : environment_(environment),
      write_observation_(std::move(write_observation)),
      step_answered_(std::move(step_answered)) {
  reset_service_ = node.advertiseService(names::kResetService, &EnvironmentServices::reset, this);
  step_service_ = node.advertiseService(names::kStepService, &EnvironmentServices::step, this);
}

bool EnvironmentServices::reset(Reset::Request& request, Reset::Response& response) {
  response.status = runWithStatus([&] {
    const StepResult result = environment_.reset(request.seed, toResetOptions(request));
    write_observation_(result, response.observation);
  });
  if (response.status.code != Status::OK) {
    ROS_WARN_STREAM("reset (seed " << request.seed << ") refused: " << response.status.message);
  }
  return true;  // the status carries errors; false would hide the response from the client
}

bool EnvironmentServices::step(Step::Request& request, Step::Response& response) {
  const auto started = std::chrono::steady_clock::now();
  StepResult result;
  response.status = runWithStatus([&] {
    Action action;
    action.d_azimuth_rad = request.action.d_azimuth;
    action.d_elevation_rad = request.action.d_elevation;
    result = environment_.step(action);
    response.reward = result.reward;
    response.terminated = result.terminated;
    response.truncated = result.truncated;
    response.occlusion_pixels = result.info.occlusion.total_pixels;
    write_observation_(result, response.observation);
  });
  if (response.status.code != Status::OK) {
    ROS_WARN_STREAM("step refused: " << response.status.message);
  } else if (step_answered_) {
    step_answered_(
        result, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  }
  return true;
}

}  // namespace occlusion_env
