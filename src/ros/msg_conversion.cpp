#include "occlusion_env/ros/msg_conversion.hpp"

#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace occlusion_env {
namespace {

const std::string& encodingOf(const cv::Mat& mat) {
  switch (mat.type()) {
    case CV_8UC3:
      return sensor_msgs::image_encodings::RGB8;
    case CV_32FC1:
      return sensor_msgs::image_encodings::TYPE_32FC1;
    case CV_8UC1:
      return sensor_msgs::image_encodings::MONO8;
    case CV_16UC1:
      return sensor_msgs::image_encodings::TYPE_16UC1;
    default:
      throw std::invalid_argument("fillImage: unsupported cv::Mat type " +
                                  std::to_string(mat.type()));
  }
}

}  // namespace

void fillImage(const cv::Mat& mat, const std_msgs::Header& header, sensor_msgs::Image& image) {
  image.header = header;
  image.encoding = encodingOf(mat);
  image.height = static_cast<std::uint32_t>(mat.rows);
  image.width = static_cast<std::uint32_t>(mat.cols);
  image.is_bigendian = 0;
  const std::size_t row_bytes = mat.cols * mat.elemSize();
  image.step = static_cast<std::uint32_t>(row_bytes);
  image.data.resize(row_bytes * mat.rows);
  if (mat.isContinuous()) {
    std::memcpy(image.data.data(), mat.data, image.data.size());
  } else {
    for (int row = 0; row < mat.rows; ++row) {
      std::memcpy(image.data.data() + row * row_bytes, mat.ptr(row), row_bytes);
    }
  }
}

cv::Mat imageView(const sensor_msgs::Image& image, const std::string& encoding, int type) {
  if (image.width == 0 && image.height == 0) return cv::Mat();
  if (image.encoding != encoding) {
    throw std::invalid_argument("image encoding " + image.encoding + ", expected " + encoding);
  }
  const std::size_t row_bytes = image.width * CV_ELEM_SIZE(type);
  if (image.step < row_bytes ||
      image.data.size() < static_cast<std::size_t>(image.step) * image.height) {
    throw std::invalid_argument("image data smaller than its width, height and step say");
  }
  // The core reads observations only; the const_cast lets cv::Mat wrap the buffer without a copy.
  return cv::Mat(static_cast<int>(image.height), static_cast<int>(image.width), type,
                 const_cast<std::uint8_t*>(image.data.data()), image.step);
}

void toMetricDepth(const sensor_msgs::Image& image, cv::Mat& depth_m) {
  namespace enc = sensor_msgs::image_encodings;
  if (image.is_bigendian) throw std::invalid_argument("big-endian depth images are not supported");
  if (image.encoding == enc::TYPE_16UC1 || image.encoding == enc::MONO16) {
    fromMillimetreDepth(imageView(image, image.encoding, CV_16UC1), depth_m);
    return;
  }
  if (image.encoding != enc::TYPE_32FC1) {
    throw std::invalid_argument("depth encoding " + image.encoding +
                                ", expected 32FC1 [m] or 16UC1 [mm] (REP 118)");
  }
  const cv::Mat metres = imageView(image, enc::TYPE_32FC1, CV_32FC1);
  depth_m.create(metres.size(), CV_32FC1);
  const float no_reading = std::numeric_limits<float>::quiet_NaN();
  for (int row = 0; row < metres.rows; ++row) {
    const float* in = metres.ptr<float>(row);
    float* out = depth_m.ptr<float>(row);
    for (int col = 0; col < metres.cols; ++col) {
      // REP 118: NaN no reading, +inf too far, -inf too close; 0 is what some drivers send.
      out[col] = std::isfinite(in[col]) && in[col] > 0.0f ? in[col] : no_reading;
    }
  }
}

sensor_msgs::CameraInfo toCameraInfo(const CameraIntrinsics& intrinsics,
                                     const std_msgs::Header& header) {
  sensor_msgs::CameraInfo info;
  info.header = header;
  info.width = static_cast<std::uint32_t>(intrinsics.width);
  info.height = static_cast<std::uint32_t>(intrinsics.height);
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {intrinsics.fx, 0.0, intrinsics.cx, 0.0, intrinsics.fy, intrinsics.cy, 0.0, 0.0, 1.0};
  info.R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info.P = {intrinsics.fx, 0.0, intrinsics.cx, 0.0, 0.0, intrinsics.fy,
            intrinsics.cy, 0.0, 0.0,           0.0, 1.0, 0.0};
  return info;
}

CameraIntrinsics intrinsicsOf(const sensor_msgs::CameraInfo& info) {
  CameraIntrinsics intrinsics;
  intrinsics.width = static_cast<int>(info.width);
  intrinsics.height = static_cast<int>(info.height);
  intrinsics.fx = info.K[0];
  intrinsics.fy = info.K[4];
  intrinsics.cx = info.K[2];
  intrinsics.cy = info.K[5];
  return intrinsics;
}

geometry_msgs::Pose toPose(const Eigen::Isometry3d& transform) {
  return tf2::toMsg(transform);
}

geometry_msgs::TransformStamped toTransform(const Eigen::Isometry3d& parent_from_child,
                                            const ros::Time& stamp, const std::string& parent,
                                            const std::string& child) {
  geometry_msgs::TransformStamped transform = tf2::eigenToTransform(parent_from_child);
  transform.header.stamp = stamp;
  transform.header.frame_id = parent;
  transform.child_frame_id = child;
  return transform;
}

geometry_msgs::TransformStamped bodyToOpticalTransform(const ros::Time& stamp,
                                                       const std::string& camera_frame,
                                                       const std::string& optical_frame) {
  Eigen::Isometry3d body_from_optical = Eigen::Isometry3d::Identity();
  body_from_optical.linear() = bodyFromOpticalRotation();
  return toTransform(body_from_optical, stamp, camera_frame, optical_frame);
}

ResetOptions toResetOptions(const Reset::Request& request) {
  ResetOptions overrides;
  if (!request.preset.empty()) overrides.preset = request.preset;
  overrides.object_ids = request.object_ids;
  overrides.categories = request.categories;
  if (request.set_start_azimuth) overrides.start_azimuth_rad = request.start_azimuth;
  if (request.set_start_elevation) overrides.start_elevation_rad = request.start_elevation;
  return overrides;
}

Reset::Request toResetRequest(std::uint64_t seed, const ResetOptions& overrides) {
  Reset::Request request;
  request.seed = seed;
  request.preset = overrides.preset.value_or("");
  request.object_ids = overrides.object_ids;
  request.categories = overrides.categories;
  request.set_start_azimuth = overrides.start_azimuth_rad.has_value();
  request.start_azimuth = overrides.start_azimuth_rad.value_or(0.0);
  request.set_start_elevation = overrides.start_elevation_rad.has_value();
  request.start_elevation = overrides.start_elevation_rad.value_or(0.0);
  return request;
}

OcclusionFigures toOcclusionFigures(const OcclusionStats& stats) {
  OcclusionFigures figures;
  figures.total_pixels = stats.total_pixels;
  figures.occluded_area_pixels = stats.occluded_area_pixels;
  figures.union_pixels = stats.union_pixels;
  figures.pairs.reserve(stats.pairs.size());
  for (const PairOcclusion& pair : stats.pairs) {
    OcclusionPair message;
    message.first = static_cast<std::uint8_t>(pair.first);
    message.second = static_cast<std::uint8_t>(pair.second);
    message.pixels = pair.pixels;
    figures.pairs.push_back(message);
  }
  return figures;
}

void fillObservation(const Environment& environment, const std_msgs::Header& header,
                     const std::string& world_frame, CameraObservation& message) {
  const Observation& observation = environment.observation();
  const StepInfo& info = environment.info();
  message.header = header;
  fillImage(observation.rgb, header, message.rgb);
  fillImage(observation.depth, header, message.depth);
  fillImage(observation.occlusion_mask, header, message.occlusion_mask);
  fillImage(observation.instance, header, message.instance_mask);
  message.camera_info = toCameraInfo(environment.intrinsics(), header);
  message.camera_pose.header.stamp = header.stamp;
  message.camera_pose.header.frame_id = world_frame;
  message.camera_pose.pose = toPose(info.world_from_optical);
  message.azimuth = info.pose.azimuth_rad;
  message.elevation = info.pose.elevation_rad;
  message.step_index = info.step_index;
  message.occlusion = toOcclusionFigures(info.occlusion);
  message.occlusion_source = CameraObservation::GROUND_TRUTH;
  const std::vector<SceneObject>& objects = environment.scene().objects;
  message.object_ids.resize(objects.size());
  message.object_categories.resize(objects.size());
  for (std::size_t k = 0; k < objects.size(); ++k) {
    message.object_ids[k] = objects[k].model->info.id;
    message.object_categories[k] = objects[k].model->info.category;
  }
}

void viewObservation(const CameraObservation& message, Observation& observation, StepInfo& info) {
  namespace enc = sensor_msgs::image_encodings;
  observation.rgb = imageView(message.rgb, enc::RGB8, CV_8UC3);
  observation.depth = imageView(message.depth, enc::TYPE_32FC1, CV_32FC1);
  observation.instance = imageView(message.instance_mask, enc::MONO8, CV_8UC1);
  observation.occlusion_mask = imageView(message.occlusion_mask, enc::MONO8, CV_8UC1);
  observation.amodal_bits.release();
  info.pose.azimuth_rad = message.azimuth;
  info.pose.elevation_rad = message.elevation;
  info.step_index = message.step_index;
  info.occlusion.total_pixels = message.occlusion.total_pixels;
  info.occlusion.occluded_area_pixels = message.occlusion.occluded_area_pixels;
  info.occlusion.union_pixels = message.occlusion.union_pixels;
  info.occlusion_source =
      message.occlusion_source == CameraObservation::ESTIMATED     ? OcclusionSource::kEstimated
      : message.occlusion_source == CameraObservation::UNAVAILABLE ? OcclusionSource::kUnavailable
                                                                   : OcclusionSource::kGroundTruth;
  info.occlusion.pairs.resize(message.occlusion.pairs.size());  // throws beyond kMaxObjectPairs
  for (std::size_t i = 0; i < message.occlusion.pairs.size(); ++i) {
    info.occlusion.pairs[i].first = message.occlusion.pairs[i].first;
    info.occlusion.pairs[i].second = message.occlusion.pairs[i].second;
    info.occlusion.pairs[i].pixels = message.occlusion.pairs[i].pixels;
  }
  tf2::fromMsg(message.camera_pose.pose, info.world_from_optical);
  info.intrinsics = intrinsicsOf(message.camera_info);
}

EpisodeReport toEpisodeReport(const EpisodeRecord& record, int episode_index,
                              const ros::Time& stamp) {
  EpisodeReport report;
  report.header.stamp = stamp;
  report.agent = record.agent;
  report.scene_set = record.scene_set;
  report.episode_index = episode_index;
  report.seed = record.scene_seed;
  report.start_azimuth = record.start_azimuth_rad;
  report.end = toString(record.end);
  report.completed = record.completed();
  report.success = record.success();
  report.steps = record.steps;
  report.max_steps = record.max_steps;
  report.final_occlusion_pixels = record.final_occlusion_px;
  report.azimuths.reserve(record.path.size());
  report.elevations.reserve(record.path.size());
  for (const SphericalPose& pose : record.path) {
    report.azimuths.push_back(pose.azimuth_rad);
    report.elevations.push_back(pose.elevation_rad);
  }
  report.wall_time = record.wall_time_s;
  report.message = record.message;
  return report;
}

EpisodeRecord fromEpisodeReport(const EpisodeReport& report) {
  if (report.azimuths.size() != report.elevations.size()) {
    throw std::invalid_argument("episode report: azimuths and elevations differ in length");
  }
  EpisodeRecord record;
  record.agent = report.agent;
  record.scene_set = report.scene_set;
  record.scene_seed = report.seed;
  record.start_azimuth_rad = report.start_azimuth;
  record.end = parseEpisodeEnd(report.end);
  record.steps = report.steps;
  record.max_steps = report.max_steps;
  record.final_occlusion_px = report.final_occlusion_pixels;
  for (std::size_t i = 0; i < report.azimuths.size(); ++i) {
    record.path.push_back({report.azimuths[i], report.elevations[i]});
  }
  record.wall_time_s = report.wall_time;
  record.message = report.message;
  return record;
}

visualization_msgs::MarkerArray toSceneMarkers(const Scene& scene, const std_msgs::Header& header) {
  visualization_msgs::MarkerArray markers;
  visualization_msgs::Marker clear;
  clear.header = header;
  clear.action = visualization_msgs::Marker::DELETEALL;
  markers.markers.push_back(clear);
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    const SceneObject& object = scene.objects[k];
    const Mesh& mesh = object.model->render;
    visualization_msgs::Marker marker;
    marker.header = header;
    marker.ns = "objects";
    marker.id = static_cast<int>(k);
    marker.type = visualization_msgs::Marker::TRIANGLE_LIST;
    marker.action = visualization_msgs::Marker::ADD;
    // A scaled scene (camera randomisation): the mesh and its place times scene.scale.
    marker.pose.position.x = scene.scale * object.position_m.x();
    marker.pose.position.y = scene.scale * object.position_m.y();
    marker.pose.position.z = scene.scale * object.position_m.z();
    marker.pose.orientation.w = 1.0;
    marker.scale.x = marker.scale.y = marker.scale.z = scene.scale;
    marker.color.r = marker.color.g = marker.color.b = marker.color.a = 1.0;
    marker.points.resize(mesh.indices.size());
    marker.colors.resize(mesh.indices.size());
    for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
      const Eigen::Vector3f& position = mesh.positions[mesh.indices[i]];
      const Eigen::Vector3f& color = mesh.colors[mesh.indices[i]];
      marker.points[i].x = position.x();
      marker.points[i].y = position.y();
      marker.points[i].z = position.z();
      marker.colors[i].r = color.x();
      marker.colors[i].g = color.y();
      marker.colors[i].b = color.z();
      marker.colors[i].a = 1.0f;
    }
    markers.markers.push_back(std::move(marker));
  }
  return markers;
}

}  // namespace occlusion_env
