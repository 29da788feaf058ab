#include "occlusion_env/ros/simulator_node.hpp"

#include <boost/make_shared.hpp>
#include <sstream>

#include "occlusion_env/StepOutcome.h"
#include "occlusion_env/core/errors.hpp"
#include "occlusion_env/ros/msg_conversion.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/status.hpp"

namespace occlusion_env {
namespace {

std::string joined(const std::vector<std::string>& items) {
  std::ostringstream text;
  for (std::size_t i = 0; i < items.size(); ++i) text << (i ? ", " : "") << items[i];
  return text.str();
}

}  // namespace

SimulatorNode::SimulatorNode(const SimulatorOptions& options, ros::NodeHandle node,
                             ros::NodeHandle private_node)
    : options_(options),
      node_(std::move(node)),
      private_node_(std::move(private_node)),
      environment_(options.environment),
      analytic_gradient_(makeAnalyticGradient(options.gradient)),
      finite_difference_gradient_(makeFiniteDifferenceGradient(options.gradient)),
      image_transport_(node_) {
  validateObjectParameters();

  rgb_publisher_ = image_transport_.advertiseCamera(names::kRgbImageTopic, 2);
  depth_publisher_ = image_transport_.advertiseCamera(names::kDepthImageTopic, 2);
  occlusion_mask_publisher_ = image_transport_.advertise(names::kOcclusionMaskTopic, 2);
  instance_mask_publisher_ = image_transport_.advertise(names::kInstanceMaskTopic, 2);
  scene_markers_publisher_ = node_.advertise<visualization_msgs::MarkerArray>(
      names::kSceneMarkersTopic, 1, /*latch=*/true);
  step_outcome_publisher_ = node_.advertise<StepOutcome>(names::kStepOutcomeTopic, 10);

  // The optical frame is fixed to the body frame; only world -> body moves.
  Eigen::Isometry3d body_from_optical = Eigen::Isometry3d::Identity();
  body_from_optical.linear() = bodyFromOpticalRotation();
  static_transform_broadcaster_.sendTransform(toTransform(
      body_from_optical, ros::Time::now(), options_.camera_frame, options_.optical_frame));

  if (options_.start_seed >= 0) {
    Reset::Request request;
    Reset::Response response;
    request.seed = static_cast<std::uint64_t>(options_.start_seed);
    reset(request, response);
    if (response.status.code != Status::OK) {
      throw ParameterError("the start-up reset with ~start_seed " +
                           std::to_string(options_.start_seed) +
                           " failed: " + response.status.message);
    }
  }

  reset_service_ = node_.advertiseService(names::kResetService, &SimulatorNode::reset, this);
  step_service_ = node_.advertiseService(names::kStepService, &SimulatorNode::step, this);
  gradient_service_ =
      node_.advertiseService(names::kGradientService, &SimulatorNode::getOcclusionGradient, this);
  move_subscriber_ = node_.subscribe(names::kMoveTopic, 10, &SimulatorNode::onMove, this);
  if (options_.tf_rate_hz > 0.0) {
    tf_timer_ = node_.createTimer(ros::Duration(1.0 / options_.tf_rate_hz),
                                  &SimulatorNode::onTfTimer, this);
  }
}

void SimulatorNode::validateObjectParameters() {
  const ObjectCatalog& catalog = environment_.library().catalog();
  for (const std::string& id : options_.environment.scene.object_ids) {
    if (catalog.find(id) == nullptr) {
      throw ParameterError("parameter " + private_node_.resolveName("object_ids") +
                           ": unknown object id '" + id + "' in the " + catalog.sourceName() +
                           " catalogue");
    }
  }
  for (const std::string& category : options_.environment.scene.categories) {
    if (catalog.idsInCategory(category).empty()) {
      throw ParameterError("parameter " + private_node_.resolveName("categories") +
                           ": no object of category '" + category + "' in the " +
                           catalog.sourceName() +
                           " catalogue (it has: " + joined(catalog.categories()) + ")");
    }
  }
}

std_msgs::Header SimulatorNode::viewHeader() const {
  std_msgs::Header header;
  header.stamp = ros::Time::now();
  header.frame_id = options_.optical_frame;
  return header;
}

bool SimulatorNode::reset(Reset::Request& request, Reset::Response& response) {
  response.status = runWithStatus([&] {
    ResetOptions overrides;
    if (!request.preset.empty()) overrides.preset = request.preset;
    overrides.object_ids = request.object_ids;
    overrides.categories = request.categories;
    if (request.set_start_azimuth) overrides.start_azimuth_rad = request.start_azimuth;
    if (request.set_start_elevation) overrides.start_elevation_rad = request.start_elevation;
    environment_.reset(request.seed, overrides);
    const std_msgs::Header header = viewHeader();
    fillObservation(environment_, header, options_.world_frame, response.observation);
    publishView(header, /*scene_changed=*/true);
  });
  if (response.status.code != Status::OK) {
    ROS_WARN_STREAM("reset (seed " << request.seed << ") refused: " << response.status.message);
  }
  return true;  // the status carries errors; false would hide the response from the client
}

Status SimulatorNode::applyStep(const CameraMove& move, StepResult& result) {
  return runWithStatus([&] {
    Action action;
    action.d_azimuth_rad = move.d_azimuth;
    action.d_elevation_rad = move.d_elevation;
    result = environment_.step(action);
  });
}

bool SimulatorNode::step(Step::Request& request, Step::Response& response) {
  StepResult result;
  response.status = applyStep(request.action, result);
  if (response.status.code == Status::OK) {
    response.reward = result.reward;
    response.terminated = result.terminated;
    response.truncated = result.truncated;
    response.occlusion_pixels = result.info.occlusion.total_pixels;
    response.status = runWithStatus([&] {
      const std_msgs::Header header = viewHeader();
      fillObservation(environment_, header, options_.world_frame, response.observation);
      publishView(header, /*scene_changed=*/false);
    });
  }
  if (response.status.code != Status::OK) {
    ROS_WARN_STREAM("step refused: " << response.status.message);
  }
  return true;
}

bool SimulatorNode::getOcclusionGradient(GetOcclusionGradient::Request& request,
                                         GetOcclusionGradient::Response& response) {
  response.status = runWithStatus([&] {
    std::uint8_t method = request.method;
    if (method == GetOcclusionGradient::Request::DEFAULT) {
      method = options_.gradient_method == "finite_difference"
                   ? GetOcclusionGradient::Request::FINITE_DIFFERENCE
                   : GetOcclusionGradient::Request::ANALYTIC;
    }
    OcclusionGradient* gradient = nullptr;
    if (method == GetOcclusionGradient::Request::ANALYTIC) gradient = analytic_gradient_.get();
    if (method == GetOcclusionGradient::Request::FINITE_DIFFERENCE) {
      gradient = finite_difference_gradient_.get();
    }
    if (gradient == nullptr) {
      throw InvalidArgumentError("unknown gradient method " + std::to_string(method) +
                                 " (0 default, 1 analytic, 2 finite difference)");
    }
    if (!environment_.hasEpisode()) throw InvalidStateError("no episode: call reset first");
    const GradientResult result = gradient->compute(environment_);
    response.d_azimuth = result.gradient.x();
    response.d_elevation = result.gradient.y();
    response.loss = result.loss;
    response.valid = result.valid;
    response.reason = result.reason;
    response.method_name = gradient->name();
  });
  if (response.status.code != Status::OK) {
    ROS_WARN_STREAM("get_occlusion_gradient refused: " << response.status.message);
  }
  return true;
}

void SimulatorNode::onMove(const CameraMove::ConstPtr& move) {
  StepResult result;
  StepOutcome outcome;
  outcome.header.stamp = ros::Time::now();
  outcome.header.frame_id = options_.world_frame;
  outcome.status = applyStep(*move, result);
  if (outcome.status.code == Status::OK) {
    outcome.reward = result.reward;
    outcome.terminated = result.terminated;
    outcome.truncated = result.truncated;
    outcome.occlusion_pixels = result.info.occlusion.total_pixels;
    outcome.azimuth = result.info.pose.azimuth_rad;
    outcome.elevation = result.info.pose.elevation_rad;
    outcome.step_index = result.info.step_index;
    outcome.status = runWithStatus([&] { publishView(viewHeader(), /*scene_changed=*/false); });
  }
  if (outcome.status.code != Status::OK) {
    ROS_WARN_STREAM("move refused: " << outcome.status.message);
  }
  step_outcome_publisher_.publish(outcome);
}

void SimulatorNode::publishView(const std_msgs::Header& header, bool scene_changed) {
  const Observation& observation = environment_.observation();
  if (rgb_publisher_.getNumSubscribers() > 0 || depth_publisher_.getNumSubscribers() > 0) {
    const auto camera_info = boost::make_shared<sensor_msgs::CameraInfo>(
        toCameraInfo(environment_.intrinsics(), header));
    if (rgb_publisher_.getNumSubscribers() > 0) {
      auto image = boost::make_shared<sensor_msgs::Image>();
      fillImage(observation.rgb, header, *image);
      rgb_publisher_.publish(image, camera_info);
    }
    if (depth_publisher_.getNumSubscribers() > 0) {
      auto image = boost::make_shared<sensor_msgs::Image>();
      fillImage(observation.depth, header, *image);
      depth_publisher_.publish(image, camera_info);
    }
  }
  if (occlusion_mask_publisher_.getNumSubscribers() > 0) {
    auto image = boost::make_shared<sensor_msgs::Image>();
    fillImage(observation.occlusion_mask, header, *image);
    occlusion_mask_publisher_.publish(image);
  }
  if (instance_mask_publisher_.getNumSubscribers() > 0) {
    auto image = boost::make_shared<sensor_msgs::Image>();
    fillImage(observation.instance, header, *image);
    instance_mask_publisher_.publish(image);
  }
  broadcastCameraTransform(header.stamp);
  if (scene_changed) {
    std_msgs::Header marker_header = header;
    marker_header.frame_id = options_.world_frame;
    scene_markers_publisher_.publish(toSceneMarkers(environment_.scene(), marker_header));
  }
}

void SimulatorNode::broadcastCameraTransform(const ros::Time& stamp) {
  if (!environment_.hasEpisode()) return;
  const Eigen::Isometry3d world_from_body =
      environment_.camera().worldFromBody(environment_.info().pose);
  transform_broadcaster_.sendTransform(
      toTransform(world_from_body, stamp, options_.world_frame, options_.camera_frame));
}

void SimulatorNode::onTfTimer(const ros::TimerEvent& /*event*/) {
  broadcastCameraTransform(ros::Time::now());
}

}  // namespace occlusion_env
