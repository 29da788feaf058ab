#include "occlusion_env/dataset/bop_dataset.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace dataset {
namespace {

namespace fs = std::filesystem;

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidArgumentError("dataset: cannot read " + path);
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    throw InvalidArgumentError("dataset: " + path + " is not valid JSON: " + error.what());
  }
}

// A frame's intrinsics: scene_camera.json's row-major cam_K, and the image size its label's drawn
// camera names (randomised sets) or the dataset's square `size`.
CameraIntrinsics intrinsicsFromJson(const nlohmann::json& camera, const nlohmann::json& label,
                                    int size) {
  const nlohmann::json& k = camera.at("cam_K");
  CameraIntrinsics intrinsics;
  intrinsics.fx = k.at(0).get<double>();
  intrinsics.cx = k.at(2).get<double>();
  intrinsics.fy = k.at(4).get<double>();
  intrinsics.cy = k.at(5).get<double>();
  const bool drawn = label.contains("camera") && label.at("camera").contains("width");
  intrinsics.width = drawn ? label.at("camera").at("width").get<int>() : size;
  intrinsics.height = drawn ? label.at("camera").at("height").get<int>() : size;
  return intrinsics;
}

nlohmann::json directionJson(const std::optional<Direction>& direction) {
  if (!direction) return nullptr;
  return {{"sin", direction->sin}, {"cos", direction->cos}, {"angle_rad", direction->angle_rad}};
}

std::optional<Direction> directionFromJson(const nlohmann::json& json) {
  if (json.is_null()) return std::nullopt;
  Direction direction;
  direction.sin = json.at("sin").get<double>();
  direction.cos = json.at("cos").get<double>();
  direction.angle_rad = json.at("angle_rad").get<double>();
  return direction;
}

cv::Mat readImage(const std::string& path, int flags, int type) {
  const cv::Mat image = cv::imread(path, flags);
  if (image.empty() || image.type() != type) {
    throw InvalidArgumentError("dataset: cannot read " + path + " as the expected image type");
  }
  return image;
}

}  // namespace

std::string idName(int id) {
  char name[16];
  std::snprintf(name, sizeof name, "%06d", id);
  return name;
}

std::string sceneFolder(const std::string& dir, int scene_index) {
  return (fs::path(dir) / kSplitFolder / idName(scene_index)).string();
}

nlohmann::json toJson(const FrameLabels& labels) {
  nlohmann::json json = {
      {"azimuth_rad", labels.pose.azimuth_rad},
      {"elevation_rad", labels.pose.elevation_rad},
      {"occlusion_px", labels.occlusion_px},
      {"smooth_loss_px", labels.smooth_loss_px},
      {"gradient_px_per_rad", {labels.gradient_azimuth, labels.gradient_elevation}},
      {"gradient_valid", labels.gradient_valid},
      {"descent_direction", directionJson(labels.descent)},
      {"oracle_steps", labels.has_oracle ? nlohmann::json(labels.oracle_steps) : nullptr},
      {"escape_direction", directionJson(labels.escape)}};
  if (!labels.shortest_first_moves.empty()) {
    // Character k: '1' when a move in direction 2 pi k / length is as short as the oracle's.
    std::string moves;
    for (const std::uint8_t shortest : labels.shortest_first_moves) moves += shortest ? '1' : '0';
    json["shortest_first_moves"] = moves;
  }
  if (labels.setup) json.update(labels.setup->toJson());
  return json;
}

FrameLabels labelsFromJson(const nlohmann::json& json, int image_id) {
  FrameLabels labels;
  labels.image_id = image_id;
  labels.pose.azimuth_rad = json.at("azimuth_rad").get<double>();
  labels.pose.elevation_rad = json.at("elevation_rad").get<double>();
  labels.occlusion_px = json.at("occlusion_px").get<std::int64_t>();
  labels.smooth_loss_px = json.at("smooth_loss_px").get<double>();
  labels.gradient_azimuth = json.at("gradient_px_per_rad").at(0).get<double>();
  labels.gradient_elevation = json.at("gradient_px_per_rad").at(1).get<double>();
  labels.gradient_valid = json.at("gradient_valid").get<bool>();
  labels.descent = directionFromJson(json.at("descent_direction"));
  labels.has_oracle = !json.at("oracle_steps").is_null();
  labels.oracle_steps = labels.has_oracle ? json.at("oracle_steps").get<int>() : -1;
  labels.escape = directionFromJson(json.at("escape_direction"));
  if (json.contains("shortest_first_moves")) {
    for (const char c : json.at("shortest_first_moves").get<std::string>()) {
      if (c != '0' && c != '1') {
        throw InvalidArgumentError("dataset: shortest_first_moves holds a character not 0 or 1");
      }
      labels.shortest_first_moves.push_back(c == '1' ? 1 : 0);
    }
  }
  if (json.contains("world")) labels.setup = SceneSetup::fromJson(json);
  return labels;
}

BopDataset::BopDataset(const std::string& dir) : dir_(dir) {
  manifest_ = readJson((fs::path(dir) / kManifestFile).string());
  try {
    const int size = manifest_.at("options").value("size", 0);
    const nlohmann::json& scenes = manifest_.at("scenes");
    scene_count_ = static_cast<int>(scenes.size());
    for (const nlohmann::json& scene : scenes) {
      const int index = scene.at("index").get<int>();
      const std::string folder = sceneFolder(dir, index);
      const std::string labels_path = (fs::path(folder) / kLabelsFile).string();
      if (!fs::exists(labels_path)) continue;  // not generated (yet)
      const nlohmann::json labels = readJson(labels_path);
      const std::string camera_path = (fs::path(folder) / "scene_camera.json").string();
      const nlohmann::json cameras =
          fs::exists(camera_path) ? readJson(camera_path) : nlohmann::json::object();
      for (const auto& [key, value] : labels.items()) {
        Frame frame;
        frame.scene_index = index;
        frame.scene_seed = scene.at("seed").get<std::uint64_t>();
        frame.validation = scene.at("split").get<std::string>() == "val";
        const int image_id = std::stoi(key);
        frame.labels = labelsFromJson(value, image_id);
        if (cameras.contains(key)) {
          frame.intrinsics = intrinsicsFromJson(cameras.at(key), value, size);
          frame.depth_scale_mm = cameras.at(key).value("depth_scale", kUnrecordedDepthScaleMm);
        }
        frame.scene_folder = folder;
        frame.rgb_path = folder + "/rgb/" + idName(image_id) + ".png";
        frame.depth_path = folder + "/depth/" + idName(image_id) + ".png";
        frame.occlusion_path = folder + "/occlusion/" + idName(image_id) + ".png";
        frames_.push_back(std::move(frame));
      }
    }
  } catch (const nlohmann::json::exception& error) {
    throw InvalidArgumentError("dataset " + dir +
                               ": malformed manifest or labels: " + error.what());
  }
}

cv::Mat BopDataset::readRgb(const Frame& frame) const {
  cv::Mat bgr = readImage(frame.rgb_path, cv::IMREAD_COLOR, CV_8UC3);
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

cv::Mat BopDataset::readDepthMeters(const Frame& frame) const {
  const cv::Mat raw = readImage(frame.depth_path, cv::IMREAD_UNCHANGED, CV_16UC1);
  cv::Mat depth(raw.size(), CV_32FC1);
  const float scale = static_cast<float>(frame.depth_scale_mm / 1000.0);
  for (int row = 0; row < raw.rows; ++row) {
    const std::uint16_t* in = raw.ptr<std::uint16_t>(row);
    float* out = depth.ptr<float>(row);
    for (int col = 0; col < raw.cols; ++col) {
      out[col] = in[col] == 0 ? std::numeric_limits<float>::quiet_NaN() : in[col] * scale;
    }
  }
  return depth;
}

cv::Mat BopDataset::readOcclusionMask(const Frame& frame) const {
  return readImage(frame.occlusion_path, cv::IMREAD_GRAYSCALE, CV_8UC1);
}

std::vector<cv::Mat> BopDataset::readUnoccludedObjectMasks(const Frame& frame,
                                                           int min_pixels) const {
  const std::string info_path = frame.scene_folder + "/scene_gt_info.json";
  const nlohmann::json info = readJson(info_path);
  std::vector<cv::Mat> masks;
  try {
    const nlohmann::json& objects = info.at(std::to_string(frame.labels.image_id));
    for (std::size_t k = 0; k < objects.size(); ++k) {
      const int all = objects[k].at("px_count_all").get<int>();
      const int visible = objects[k].at("px_count_visib").get<int>();
      if (visible < min_pixels || visible != all) continue;
      masks.push_back(readImage(frame.scene_folder + "/mask_visib/" +
                                    idName(frame.labels.image_id) + "_" +
                                    idName(static_cast<int>(k)) + ".png",
                                cv::IMREAD_GRAYSCALE, CV_8UC1));
    }
  } catch (const nlohmann::json::exception& error) {
    throw InvalidArgumentError("dataset: " + info_path + " is malformed: " + error.what());
  }
  return masks;
}

}  // namespace dataset
}  // namespace occlusion_env
