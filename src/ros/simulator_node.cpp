#include "occlusion_env/ros/simulator_node.hpp"

#include <boost/make_shared.hpp>
#include <sstream>

#include <tf2_msgs/TFMessage.h>

#include "occlusion_env/StepOutcome.h"
#include "occlusion_env/common/errors.hpp"
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
      analytic_gradient_(makeAnalyticGradient(options.environment.gradient)),
      finite_difference_gradient_(makeFiniteDifferenceGradient(options.environment.gradient)),
      image_transport_(node_) {
  validateObjectParameters();

  view_header_.frame_id = options_.optical_frame;
  rgb_publisher_ = advertiseView(names::kRgbImageTopic, &Observation::rgb);
  depth_publisher_ = advertiseView(names::kDepthImageTopic, &Observation::depth);
  occlusion_mask_publisher_ =
      advertiseView(names::kOcclusionMaskTopic, &Observation::occlusion_mask);
  instance_mask_publisher_ = advertiseView(names::kInstanceMaskTopic, &Observation::instance);
  tf_publisher_ = node_.advertise<tf2_msgs::TFMessage>(
      "/tf", 100, [this](const ros::SingleSubscriberPublisher& link) {
        if (view_header_.stamp.isZero()) return;
        tf2_msgs::TFMessage message;
        message.transforms.push_back(cameraTransform(view_header_.stamp));
        link.publish(message);
      });
  scene_markers_publisher_ = node_.advertise<visualization_msgs::MarkerArray>(
      names::kSceneMarkersTopic, 1, /*latch=*/true);
  step_outcome_publisher_ = node_.advertise<StepOutcome>(names::kStepOutcomeTopic, 10);

  static_transform_broadcaster_.sendTransform(
      bodyToOpticalTransform(ros::Time::now(), options_.camera_frame, options_.optical_frame));

  // Served once the constructor has returned and the caller spins: the start-up reset comes first.
  services_ = std::make_unique<EnvironmentServices>(
      node_, environment_, [this](const StepResult& result, CameraObservation& observation) {
        answerView(result, observation);
      });
  resetAtStartUp(options_.start_seed, [this](Reset::Request& request, Reset::Response& response) {
    reset(request, response);
  });

  if (options_.offer_gradient) {
    gradient_service_ =
        node_.advertiseService(names::kGradientService, &SimulatorNode::getOcclusionGradient, this);
  }
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

image_transport::CameraPublisher SimulatorNode::advertiseView(const std::string& topic,
                                                              const cv::Mat Observation::*image) {
  // The current view, sent to one new subscriber only: the others have it already.
  const auto send_image = [this, image](const image_transport::SingleSubscriberPublisher& link) {
    if (view_header_.stamp.isZero()) return;
    sensor_msgs::Image message;
    fillImage(environment_.observation().*image, view_header_, message);
    link.publish(message);
  };
  const auto send_info = [this](const ros::SingleSubscriberPublisher& link) {
    if (view_header_.stamp.isZero()) return;
    link.publish(toCameraInfo(environment_.intrinsics(), view_header_));
  };
  return image_transport_.advertiseCamera(topic, 2, send_image,
                                          image_transport::SubscriberStatusCallback(), send_info);
}

const std_msgs::Header& SimulatorNode::stampNewView() {
  view_header_.stamp = ros::Time::now();
  ++view_header_.seq;
  return view_header_;
}

bool SimulatorNode::reset(Reset::Request& request, Reset::Response& response) {
  return services_->reset(request, response);
}

bool SimulatorNode::step(Step::Request& request, Step::Response& response) {
  return services_->step(request, response);
}

void SimulatorNode::answerView(const StepResult& result, CameraObservation& observation) {
  fillObservation(environment_, stampNewView(), options_.world_frame, observation);
  publishView(/*scene_changed=*/result.info.step_index == 0);  // step 0: after a reset
}

Status SimulatorNode::applyStep(const CameraMove& move, StepResult& result) {
  return runWithStatus([&] {
    Action action;
    action.d_azimuth_rad = move.d_azimuth;
    action.d_elevation_rad = move.d_elevation;
    result = environment_.step(action);
  });
}

bool SimulatorNode::getOcclusionGradient(GetOcclusionGradient::Request& request,
                                         GetOcclusionGradient::Response& response) {
  response.status = runWithStatus([&] {
    std::uint8_t method = request.method;
    if (method == GetOcclusionGradient::Request::DEFAULT) {
      method = options_.environment.gradient_method == "finite_difference"
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
  outcome.header.frame_id = options_.world_frame;
  outcome.status = applyStep(*move, result);
  // The outcome carries the stamp of the view it led to (its images and tf); a refused move
  // changes nothing and is stamped when it was refused.
  outcome.header.stamp =
      outcome.status.code == Status::OK ? stampNewView().stamp : ros::Time::now();
  if (outcome.status.code == Status::OK) {
    outcome.reward = result.reward;
    outcome.terminated = result.terminated;
    outcome.truncated = result.truncated;
    outcome.occlusion_pixels = result.info.occlusion.total_pixels;
    outcome.azimuth = result.info.pose.azimuth_rad;
    outcome.elevation = result.info.pose.elevation_rad;
    outcome.step_index = result.info.step_index;
    outcome.status = runWithStatus([&] { publishView(/*scene_changed=*/false); });
  }
  if (outcome.status.code != Status::OK) {
    ROS_WARN_STREAM("move refused: " << outcome.status.message);
  }
  step_outcome_publisher_.publish(outcome);
}

void SimulatorNode::publishView(bool scene_changed) {
  const std_msgs::Header& header = view_header_;
  const Observation& observation = environment_.observation();
  // One CameraInfo for every image topic, built only when one has a subscriber.
  boost::shared_ptr<sensor_msgs::CameraInfo> camera_info;
  for (auto [publisher, mat] :
       {std::make_pair(&rgb_publisher_, &observation.rgb),
        std::make_pair(&depth_publisher_, &observation.depth),
        std::make_pair(&occlusion_mask_publisher_, &observation.occlusion_mask),
        std::make_pair(&instance_mask_publisher_, &observation.instance)}) {
    if (publisher->getNumSubscribers() == 0) continue;
    if (!camera_info) {
      camera_info = boost::make_shared<sensor_msgs::CameraInfo>(
          toCameraInfo(environment_.intrinsics(), header));
    }
    auto image = boost::make_shared<sensor_msgs::Image>();
    fillImage(*mat, header, *image);
    publisher->publish(image, camera_info);
  }
  broadcastCameraTransform(header.stamp);
  if (scene_changed) {
    std_msgs::Header marker_header = header;
    marker_header.frame_id = options_.world_frame;
    scene_markers_publisher_.publish(toSceneMarkers(environment_.scene(), marker_header));
  }
}

geometry_msgs::TransformStamped SimulatorNode::cameraTransform(const ros::Time& stamp) const {
  const Eigen::Isometry3d world_from_body =
      environment_.camera().worldFromBody(environment_.info().pose);
  return toTransform(world_from_body, stamp, options_.world_frame, options_.camera_frame);
}

void SimulatorNode::broadcastCameraTransform(const ros::Time& stamp) {
  if (!environment_.hasEpisode()) return;
  tf2_msgs::TFMessage message;
  message.transforms.push_back(cameraTransform(stamp));
  tf_publisher_.publish(message);
}

void SimulatorNode::onTfTimer(const ros::TimerEvent& /*event*/) {
  broadcastCameraTransform(ros::Time::now());
}

}  // namespace occlusion_env
