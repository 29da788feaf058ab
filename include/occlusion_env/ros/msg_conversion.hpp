// Conversions between the core's types (cv::Mat, Observation, poses, meshes) and ROS messages.
// Images are filled directly from the cv::Mat buffers: one copy, no cv_bridge.
#pragma once

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>

#include "occlusion_env/CameraObservation.h"
#include "occlusion_env/EpisodeReport.h"
#include "occlusion_env/OcclusionFigures.h"
#include "occlusion_env/Reset.h"
#include "occlusion_env/agents/episode.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/render/depth_encoding.hpp"

namespace occlusion_env {

/// Fills `image` (reusing its buffer's capacity) with `mat`'s pixels. `mat` must be CV_8UC3
/// (rgb8), CV_32FC1 (32FC1) or CV_8UC1 (mono8). Throws std::invalid_argument otherwise.
void fillImage(const cv::Mat& mat, const std_msgs::Header& header, sensor_msgs::Image& image);

/// A cv::Mat header over `image`'s pixels (no copy: valid while `image` is unchanged), checked
/// against `encoding` and `type` (e.g. "rgb8", CV_8UC3) and against the data's size. An image of
/// no pixels (a mask the camera bridge cannot give) is an empty Mat, whatever its encoding.
/// Throws std::invalid_argument.
cv::Mat imageView(const sensor_msgs::Image& image, const std::string& encoding, int type);

/// A depth image of either REP 118 encoding as metres: 32FC1 [m] (NaN, inf and values <= 0 are
/// no reading) or 16UC1 [mm] (0 is no reading). `depth_m` (CV_32FC1, reused) gets NaN wherever
/// there is no reading, the package's convention. Throws std::invalid_argument on another
/// encoding, a big-endian image or data smaller than the image says.
void toMetricDepth(const sensor_msgs::Image& image, cv::Mat& depth_m);

/// Pinhole CameraInfo (plumb_bob, zero distortion, P = [K | 0]).
sensor_msgs::CameraInfo toCameraInfo(const CameraIntrinsics& intrinsics,
                                     const std_msgs::Header& header);

/// The pinhole intrinsics of `info` (size and K; distortion ignored), unchecked.
CameraIntrinsics intrinsicsOf(const sensor_msgs::CameraInfo& info);

geometry_msgs::Pose toPose(const Eigen::Isometry3d& transform);

/// `parent_from_child` as a transform from `parent` to `child` (tf's convention).
geometry_msgs::TransformStamped toTransform(const Eigen::Isometry3d& parent_from_child,
                                            const ros::Time& stamp, const std::string& parent,
                                            const std::string& child);

/// The fixed transform from the camera's body frame to its optical frame (REP 103), for a static
/// broadcaster: only world -> body moves.
geometry_msgs::TransformStamped bodyToOpticalTransform(const ros::Time& stamp,
                                                       const std::string& camera_frame,
                                                       const std::string& optical_frame);

/// The per-reset overrides a Reset request asks for (empty or false fields: none).
ResetOptions toResetOptions(const Reset::Request& request);
/// The Reset request that asks for `seed` with `overrides` (toResetOptions() reads it back).
Reset::Request toResetRequest(std::uint64_t seed, const ResetOptions& overrides);

OcclusionFigures toOcclusionFigures(const OcclusionStats& stats);

/// Fills every field of `message` from the environment's current episode. `header` carries the
/// stamp and the optical frame id; `world_frame` is the camera pose's frame.
void fillObservation(const Environment& environment, const std_msgs::Header& header,
                     const std::string& world_frame, CameraObservation& message);

/// The core's view of an observation message, for agents running behind ROS: `observation` gets
/// cv::Mat headers over the message's image buffers (no copy: valid while `message` is unchanged;
/// amodal_bits stays empty, it is not sent; an image of no pixels, as the camera bridge sends for
/// masks it cannot give, stays empty too), `info` the pose, step index, occlusion figures,
/// camera pose and intrinsics (`info.last_action` is left as it is: the message does not hold it).
/// Throws std::invalid_argument on an image of the wrong encoding or size.
void viewObservation(const CameraObservation& message, Observation& observation, StepInfo& info);

/// An episode record as a message (`episode_index`: its place in the node's list of seeds).
EpisodeReport toEpisodeReport(const EpisodeRecord& record, int episode_index,
                              const ros::Time& stamp);
/// The record a message describes. Throws std::invalid_argument on an unknown `end` or a path
/// whose azimuths and elevations differ in length.
EpisodeRecord fromEpisodeReport(const EpisodeReport& report);

/// One TRIANGLE_LIST marker per scene object (its render mesh, vertex colours), preceded by a
/// DELETEALL so that markers of an earlier scene disappear.
visualization_msgs::MarkerArray toSceneMarkers(const Scene& scene, const std_msgs::Header& header);

}  // namespace occlusion_env
