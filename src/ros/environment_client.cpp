#include "occlusion_env/ros/environment_client.hpp"

#include <sstream>
#include <stdexcept>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/ros/msg_conversion.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/status.hpp"

namespace occlusion_env {
namespace {

std::string seconds(double value) {
  std::ostringstream text;
  text << value << " s";
  return text.str();
}

}  // namespace

bool requireTrainSplit(const std::string& ns) {
  const std::string parameter = ns + "/occlusion_sim/model_split";
  std::string split;
  if (!ros::param::get(parameter, split)) return false;
  if (split != "train") {
    throw InvalidArgumentError("the simulator under " + ns + " draws models of the split '" +
                               split +
                               "', test-split models included: start it with model_split:=train "
                               "(launch/simulators.launch does by default)");
  }
  return true;
}

EnvironmentClient::EnvironmentClient(ros::NodeHandle node, const EnvironmentClientOptions& options)
    : node_(std::move(node)),
      options_(options),
      reset_name_(node_.resolveName(names::kResetService)),
      step_name_(node_.resolveName(names::kStepService)),
      gradient_name_(node_.resolveName(names::kGradientService)) {
  if (!(options_.service_timeout_s >= 0.0)) {
    throw InvalidArgumentError("service_timeout_s must be >= 0 (0 waits forever)");
  }
  if (options_.reset_attempts < 1) throw InvalidArgumentError("reset_attempts must be >= 1");
}

std::string EnvironmentClient::describe() const {
  return "the ROS services " + reset_name_ + " and " + step_name_;
}

void EnvironmentClient::connect() {
  const double timeout_s = options_.service_timeout_s;
  const ros::Duration timeout = timeout_s > 0.0 ? ros::Duration(timeout_s) : ros::Duration(-1);
  ROS_INFO_STREAM(
      "waiting for " << reset_name_ << " and " << step_name_
                     << (timeout_s > 0.0 ? " (up to " + seconds(timeout_s) + ")" : std::string()));
  if (!ros::service::waitForService(reset_name_, timeout) ||
      !ros::service::waitForService(step_name_, timeout)) {
    throw EnvironmentUnavailableError("the services " + reset_name_ + " and " + step_name_ +
                                      " did not appear within " + seconds(timeout_s));
  }
  // Fresh persistent clients: those of a node that went away cannot be reused.
  reset_client_ = node_.serviceClient<Reset>(reset_name_, /*persistent=*/true);
  step_client_ = node_.serviceClient<Step>(step_name_, /*persistent=*/true);
  // The node serving reset and step is up, so a short wait tells whether it offers the gradient.
  has_gradient_ = ros::service::waitForService(gradient_name_, ros::Duration(2.0));
  if (has_gradient_) {
    gradient_client_ =
        node_.serviceClient<GetOcclusionGradient>(gradient_name_, /*persistent=*/true);
  }
  connected_ = true;
}

StepResult EnvironmentClient::resultFor(const CameraObservation& message) {
  StepResult result;
  try {
    viewObservation(message, observation_, result.info);
  } catch (const std::exception& error) {
    throw InvalidArgumentError(std::string("unreadable observation from ") + describe() + ": " +
                               error.what());
  }
  result.observation = &observation_;
  return result;
}

StepResult EnvironmentClient::reset(std::uint64_t seed, const ResetOptions& overrides) {
  if (!connected_) connect();
  reset_call_.request = toResetRequest(seed, overrides);
  // Nothing of an episode is lost when a reset fails in transit (e.g. to a simulator still
  // shutting down after a crash): reconnect and try again, a few times.
  for (int attempt = 1; !reset_client_.call(reset_call_); ++attempt) {
    if (attempt >= options_.reset_attempts || !ros::ok()) {
      throw EnvironmentUnavailableError("the call to " + reset_name_ + " failed " +
                                        std::to_string(attempt) + " times");
    }
    ROS_WARN_STREAM("the call to " << reset_name_ << " failed; reconnecting and trying again");
    ros::WallDuration(0.2).sleep();
    connect();
  }
  throwForStatus(reset_call_.response.status, "reset refused");
  return resultFor(reset_call_.response.observation);
}

StepResult EnvironmentClient::step(const Action& action) {
  if (!connected_) throw InvalidStateError("step before any reset: call reset first");
  step_call_.request.action.d_azimuth = action.d_azimuth_rad;
  step_call_.request.action.d_elevation = action.d_elevation_rad;
  if (!step_client_.call(step_call_)) {
    throw EnvironmentUnavailableError("the call to " + step_name_ + " failed");
  }
  const Step::Response& response = step_call_.response;
  throwForStatus(response.status, "step refused");
  StepResult result = resultFor(response.observation);
  result.info.last_action = action;
  result.reward = response.reward;
  result.terminated = response.terminated;
  result.truncated = response.truncated;
  return result;
}

GradientResult EnvironmentClient::occlusionGradient() {
  if (!has_gradient_) return EnvironmentInterface::occlusionGradient();  // throws
  gradient_call_.request.method = GetOcclusionGradient::Request::DEFAULT;
  if (!gradient_client_.call(gradient_call_)) {
    throw EnvironmentUnavailableError("the call to " + gradient_name_ + " failed");
  }
  const GetOcclusionGradient::Response& response = gradient_call_.response;
  GradientResult result;
  if (response.status.code != Status::OK) {
    result.reason = "gradient refused: " + response.status.message;
    ROS_WARN_STREAM_THROTTLE(5.0, result.reason);
    return result;
  }
  result.loss = response.loss;
  result.gradient = {response.d_azimuth, response.d_elevation};
  result.valid = response.valid && result.gradient.allFinite();
  result.reason = response.reason;
  if (!result.valid) result.gradient.setZero();
  return result;
}

}  // namespace occlusion_env
