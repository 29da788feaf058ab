// Every topic, service, node and frame name of the ROS interface, in one place. Topic and service
// names are relative to the node's public namespace (kNamespace) and are meant to be remapped.
#pragma once

namespace occlusion_env {
namespace names {

// Namespace of the simulator's public NodeHandle, relative to the node's own namespace.
constexpr char kNamespace[] = "occlusion";
constexpr char kSimulatorNode[] = "occlusion_sim";

// Services.
constexpr char kResetService[] = "reset";                      // occlusion_env/Reset
constexpr char kStepService[] = "step";                        // occlusion_env/Step
constexpr char kGradientService[] = "get_occlusion_gradient";  // occlusion_env/GetOcclusionGradient

// Published topics (camera_info topics sit beside the images, as image_transport names them).
// Every image topic and its camera_info send the current view to a subscriber as it connects,
// stamped with the view's own stamp (and /tf sends it the camera transform at that stamp), so a
// late subscriber (rviz, depth_image_proc) sees the scene without waiting for the next step.
constexpr char kRgbImageTopic[] = "rgb/image_raw";                  // sensor_msgs/Image rgb8
constexpr char kRgbCameraInfoTopic[] = "rgb/camera_info";           // sensor_msgs/CameraInfo
constexpr char kDepthImageTopic[] = "depth/image_raw";              // sensor_msgs/Image 32FC1 [m]
constexpr char kDepthCameraInfoTopic[] = "depth/camera_info";       // sensor_msgs/CameraInfo
constexpr char kOcclusionMaskTopic[] = "occlusion_mask/image_raw";  // sensor_msgs/Image mono8
constexpr char kOcclusionMaskCameraInfoTopic[] = "occlusion_mask/camera_info";
constexpr char kInstanceMaskTopic[] = "instance_mask/image_raw";  // sensor_msgs/Image mono8
constexpr char kInstanceMaskCameraInfoTopic[] = "instance_mask/camera_info";
constexpr char kPointsTopic[] = "points";  // sensor_msgs/PointCloud2 (sim.launch points:=true)
constexpr char kSceneMarkersTopic[] = "scene_markers";  // visualization_msgs/MarkerArray
constexpr char kStepOutcomeTopic[] = "step_outcome";    // occlusion_env/StepOutcome

// Published by agent nodes in their private namespace.
constexpr char kEpisodesTopic[] = "episodes";  // occlusion_env/EpisodeReport, one per episode

// Subscribed topics.
constexpr char kMoveTopic[] = "move";  // occlusion_env/CameraMove

// A real camera on a robot, and the camera bridge that serves reset/step for it
// (ros/camera_bridge.hpp; the simulator in ~mode camera stands in for camera and robot).
constexpr char kCameraBridgeNode[] = "camera_bridge";
// Published by the bridge, for the robot: the pose the camera's optical frame is to take.
constexpr char kCameraGoalTopic[] = "camera_goal";  // geometry_msgs/PoseStamped
// The stand-in camera's truth, which no real camera has: tests and checks of the bridge only.
constexpr char kArrangeSceneService[] = "ground_truth/arrange_scene";  // occlusion_env/Reset
constexpr char kGroundTruthViewTopic[] = "ground_truth/view";  // occlusion_env/GroundTruthView

// Frames (REP 103/105); defaults of the ~world_frame, ~camera_frame, ~optical_frame parameters.
constexpr char kWorldFrame[] = "world";
constexpr char kCameraFrame[] = "occlusion_camera";           // body: x forward, y left, z up
constexpr char kOpticalFrame[] = "occlusion_camera_optical";  // z forward, x right, y down

}  // namespace names
}  // namespace occlusion_env
