// Training data in the BOP format (Hodan et al., BOP: Benchmark for 6D Object Pose Estimation),
// with this package's labels beside it. Layout of a dataset folder:
//
//   dataset.json                 manifest: options, tool version, model split, scene-wise
//                                train/val split, seeds, counts
//   train/<scene:06d>/           one scene per folder (<scene> = its index in the dataset)
//     rgb/<im:06d>.png           8-bit RGB
//     depth/<im:06d>.png         16-bit, depth along the optical axis = value * depth_scale [mm],
//                                0 where nothing is hit
//     mask/<im:06d>_<k:06d>.png  object k's amodal (full) silhouette, 255 inside
//     mask_visib/<im>_<k>.png    object k's visible part
//     occlusion/<im:06d>.png     where two or more silhouettes overlap, 255 inside (ours)
//     scene_camera.json          per image: cam_K (row-major), depth_scale, cam_R_w2c, cam_t_w2c
//     [mm] scene_gt.json              per image: per object cam_R_m2c, cam_t_m2c [mm], obj_id
//     scene_gt_info.json         per image: per object bbox_obj, bbox_visib, px_count_all,
//                                px_count_valid, px_count_visib, visib_fract
//     scene_labels.json          per image (ours): dataset/labels.hpp, written last: a scene
//                                folder with it is complete
//
// Everything is keyed by image id (the JSON keys, the file names): nothing depends on the order
// in which files are listed.
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "occlusion_env/dataset/labels.hpp"
#include "occlusion_env/geometry/camera.hpp"

namespace occlusion_env {
namespace dataset {

/// Depth PNG units [mm] written: 0.25 mm, up to 16.38 m (a room's far walls stand up to 12 m
/// from the camera). Each image records its own (scene_camera.json's depth_scale) and is read
/// with it: sets written before 2026-11-29 have 0.1 mm, up to 6.55 m.
constexpr double kDepthScaleMm = 0.25;
/// The depth unit [mm] of an image whose scene_camera.json records none.
constexpr double kUnrecordedDepthScaleMm = 0.1;
constexpr const char* kManifestFile = "dataset.json";
constexpr const char* kSplitFolder = "train";
constexpr const char* kLabelsFile = "scene_labels.json";

/// "<dir>/train/000012"
std::string sceneFolder(const std::string& dir, int scene_index);
/// "000007", the six-digit name of an id.
std::string idName(int id);

/// Labels <-> JSON (scene_labels.json entries).
nlohmann::json toJson(const FrameLabels& labels);
FrameLabels labelsFromJson(const nlohmann::json& json, int image_id);

/// One frame of a dataset.
struct Frame {
  int scene_index = 0;
  std::uint64_t scene_seed = 0;
  bool validation = false;  // the scene is in the validation split
  FrameLabels labels;
  /// scene_camera.json's cam_K for the frame's images; fx = 0 when the scene has none.
  CameraIntrinsics intrinsics;
  double depth_scale_mm = kUnrecordedDepthScaleMm;  // its depth PNG's unit [mm]
  std::string scene_folder;                         // "<dir>/train/<scene:06d>"
  std::string rgb_path, depth_path, occlusion_path;
};

/// Reads a dataset written by occlusion_dataset: the manifest, and the frames of every complete
/// scene. Throws InvalidArgumentError naming the file on anything missing or malformed.
class BopDataset {
 public:
  explicit BopDataset(const std::string& dir);

  const nlohmann::json& manifest() const { return manifest_; }
  const std::vector<Frame>& frames() const { return frames_; }
  int sceneCount() const { return scene_count_; }

  /// CV_8UC3 RGB.
  cv::Mat readRgb(const Frame& frame) const;
  /// CV_32FC1 [m] along the optical axis, NaN where nothing was hit (REP 118).
  cv::Mat readDepthMeters(const Frame& frame) const;
  /// CV_8UC1, 255 where occluded.
  cv::Mat readOcclusionMask(const Frame& frame) const;
  /// The visible masks (CV_8UC1, 255 inside) of the frame's objects that nothing hides (their
  /// whole silhouette is visible: px_count_visib == px_count_all) and that cover at least
  /// `min_pixels`, in object order.
  std::vector<cv::Mat> readUnoccludedObjectMasks(const Frame& frame, int min_pixels) const;

 private:
  std::string dir_;
  nlohmann::json manifest_;
  std::vector<Frame> frames_;
  int scene_count_ = 0;
};

}  // namespace dataset
}  // namespace occlusion_env
