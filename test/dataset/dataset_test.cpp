// The BOP dataset: a tiny one generated, read back by an independent reader (nlohmann::json and
// cv::imread, not the library's reader), audited, resumed and refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <set>

#include "common/temporary_dir.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/dataset/bop_dataset.hpp"
#include "occlusion_env/dataset/generator.hpp"
#include "occlusion_env/dataset/scene_writer.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/env/scene_set.hpp"

namespace occlusion_env {
namespace dataset {
namespace {

namespace fs = std::filesystem;

DatasetOptions tinyOptions() {
  DatasetOptions options;
  options.scenes = 2;
  options.frames = 12;  // more than 10: ids that sort differently as strings
  options.size = 64;
  options.threads = 2;
  options.validation_fraction = 0.5;
  return options;
}

// tinyOptions() with `scenes` scenes of `frames` frames and no oracle labels: quick sets.
DatasetOptions quickOptions(int scenes, int frames) {
  DatasetOptions options = tinyOptions();
  options.scenes = scenes;
  options.frames = frames;
  options.oracle_labels = false;
  return options;
}

// Generated once for the tests below.
const std::string& tinyDataset() {
  static const std::string dir = [] {
    const fs::path path = temporaryDir("occlusion_env_dataset_test");
    const GenerationReport report = generateDataset(path.string(), tinyOptions());
    EXPECT_EQ(report.scenes_written, 2);
    EXPECT_EQ(report.frames_written, 24);
    return path.string();
  }();
  return dir;
}

nlohmann::json readJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(DatasetTest, FilesFollowTheBopConventions) {
  const fs::path scene = fs::path(tinyDataset()) / "train" / "000001";
  const nlohmann::json camera = readJson(scene / "scene_camera.json");
  const nlohmann::json gt = readJson(scene / "scene_gt.json");
  const nlohmann::json info = readJson(scene / "scene_gt_info.json");
  ASSERT_EQ(camera.size(), 12u);
  EnvironmentOptions options;
  options.width = options.height = 64;
  const CameraIntrinsics k = CameraIntrinsics::fromFieldOfView(64, 64, options.field_of_view_rad);
  for (int image : {0, 7, 11}) {
    const std::string key = std::to_string(image);
    char name[32];
    std::snprintf(name, sizeof name, "%06d", image);
    // K, row-major; depth_scale in mm per unit.
    const std::vector<double> cam_k = camera.at(key).at("cam_K").get<std::vector<double>>();
    ASSERT_EQ(cam_k.size(), 9u);
    EXPECT_DOUBLE_EQ(cam_k[0], k.fx);
    EXPECT_DOUBLE_EQ(cam_k[2], k.cx);
    EXPECT_DOUBLE_EQ(cam_k[4], k.fy);
    EXPECT_DOUBLE_EQ(cam_k[5], k.cy);
    EXPECT_DOUBLE_EQ(cam_k[8], 1.0);
    const double depth_scale = camera.at(key).at("depth_scale").get<double>();
    // Object 0 sits at the world origin: its translation is the world's, in mm.
    const auto t_w2c = camera.at(key).at("cam_t_w2c").get<std::vector<double>>();
    const auto t_m2c = gt.at(key).at(0).at("cam_t_m2c").get<std::vector<double>>();
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(t_w2c[i], t_m2c[i], 1e-9);
    EXPECT_NEAR(std::hypot(t_w2c[0], t_w2c[1], t_w2c[2]), 4000.0, 1e-6);  // 4 m away
    // The origin projects near the image centre (the camera looks at it).
    EXPECT_NEAR(t_w2c[0], 0.0, 1e-6);
    EXPECT_NEAR(t_w2c[1], 0.0, 1e-6);
    // Depth: 16-bit, depth_scale mm per unit, 0 = nothing hit; each object's masks.
    const cv::Mat depth =
        cv::imread((scene / "depth" / (std::string(name) + ".png")).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(depth.type(), CV_16UC1);
    cv::Mat covered = cv::Mat::zeros(depth.size(), CV_8UC1);
    for (std::size_t object = 0; object < gt.at(key).size(); ++object) {
      char mask_name[48];
      std::snprintf(mask_name, sizeof mask_name, "%06d_%06zu.png", image, object);
      const cv::Mat amodal =
          cv::imread((scene / "mask" / mask_name).string(), cv::IMREAD_GRAYSCALE);
      const cv::Mat visible =
          cv::imread((scene / "mask_visib" / mask_name).string(), cv::IMREAD_GRAYSCALE);
      ASSERT_FALSE(amodal.empty());
      ASSERT_FALSE(visible.empty());
      EXPECT_EQ(cv::countNonZero(amodal), info.at(key).at(object).at("px_count_all").get<int>());
      EXPECT_EQ(cv::countNonZero(visible), info.at(key).at(object).at("px_count_visib").get<int>());
      EXPECT_EQ(cv::countNonZero(visible & ~amodal), 0) << "visible outside the full silhouette";
      covered |= visible;
    }
    // Every visible pixel has a depth, and only those; depths are metres-sized.
    EXPECT_EQ(cv::countNonZero(covered != (depth > 0)), 0);
    double max_units = 0.0;
    cv::minMaxLoc(depth, nullptr, &max_units);
    EXPECT_GT(max_units * depth_scale, 2000.0);  // [mm]
    EXPECT_LT(max_units * depth_scale, 6000.0);
  }
}

TEST(DatasetTest, LabelsAreKeyedByImageIdAndMatchTheirMasks) {
  const fs::path scene = fs::path(tinyDataset()) / "train" / "000000";
  const nlohmann::json labels = readJson(scene / "scene_labels.json");
  const nlohmann::json gt = readJson(scene / "scene_gt.json");
  ASSERT_EQ(labels.size(), 12u);
  for (const auto& [key, label] : labels.items()) {
    const int image = std::stoi(key);
    // L (Eq. 9) from this image's own mask files equals its label: masks and labels align.
    std::vector<cv::Mat> masks;
    for (std::size_t object = 0; object < gt.at(key).size(); ++object) {
      char mask_name[48];
      std::snprintf(mask_name, sizeof mask_name, "%06d_%06zu.png", image, object);
      masks.push_back(cv::imread((scene / "mask" / mask_name).string(), cv::IMREAD_GRAYSCALE));
    }
    std::int64_t pairs = 0;
    for (std::size_t i = 0; i < masks.size(); ++i) {
      for (std::size_t j = i + 1; j < masks.size(); ++j)
        pairs += cv::countNonZero(masks[i] & masks[j]);
    }
    EXPECT_EQ(pairs, label.at("occlusion_px").get<std::int64_t>()) << "image " << key;
    // Directions are unit vectors with their angle.
    if (!label.at("descent_direction").is_null()) {
      const auto& d = label.at("descent_direction");
      EXPECT_NEAR(std::hypot(d.at("sin").get<double>(), d.at("cos").get<double>()), 1.0, 1e-12);
      EXPECT_NEAR(std::atan2(d.at("sin").get<double>(), d.at("cos").get<double>()),
                  d.at("angle_rad").get<double>(), 1e-12);
    }
    EXPECT_EQ(label.at("oracle_steps").get<int>() == 0, label.at("occlusion_px").get<int>() == 0);
    // A path's shortest first moves, one character per direction of the oracle's circle, at
    // least the oracle's own; none without a path.
    const bool has_path = label.at("oracle_steps").get<int>() > 0;
    ASSERT_EQ(label.contains("shortest_first_moves"), has_path) << "image " << key;
    if (has_path) {
      const std::string moves = label.at("shortest_first_moves").get<std::string>();
      EXPECT_EQ(moves.size(), 64u);
      EXPECT_EQ(moves.find_first_not_of("01"), std::string::npos);
      EXPECT_NE(moves.find('1'), std::string::npos);
    }
  }
  // The reader gives them back as they were written.
  const BopDataset data(tinyDataset());
  for (const Frame& frame : data.frames()) {
    if (frame.scene_index != 0) continue;
    const nlohmann::json& label = labels.at(std::to_string(frame.labels.image_id));
    std::string moves;
    for (const std::uint8_t shortest : frame.labels.shortest_first_moves)
      moves += shortest ? '1' : '0';
    EXPECT_EQ(moves, label.value("shortest_first_moves", ""));
  }
  // Frame 0 is the scene's start view; later frames moved by whole steps.
  EXPECT_LT(std::abs(labels.at("0").at("azimuth_rad").get<double>()), M_PI / 32 + 1e-12);
}

TEST(DatasetTest, ReaderAuditResumeAndRefusals) {
  const std::string dir = tinyDataset();
  const BopDataset data(dir);
  EXPECT_EQ(data.frames().size(), 24u);
  EXPECT_EQ(data.sceneCount(), 2);
  int validation = 0;
  for (const Frame& frame : data.frames()) validation += frame.validation;
  EXPECT_EQ(validation, 12);  // one of the two scenes
  EXPECT_EQ(readJson(fs::path(dir) / "dataset.json").at("validation"),
            "whole scenes: those with index % 2 == 1 (one in 2)");
  const cv::Mat depth = data.readDepthMeters(data.frames().front());
  EXPECT_EQ(depth.type(), CV_32FC1);

  const AuditReport audit = auditDataset(dir, 10);
  EXPECT_EQ(audit.frames_checked, 10);
  EXPECT_EQ(audit.failures, 0) << (audit.problems.empty() ? "" : audit.problems.front());

  // Resume: nothing left to do. Other options: refused, naming them.
  const GenerationReport again = generateDataset(dir, tinyOptions());
  EXPECT_EQ(again.scenes_written, 0);
  EXPECT_EQ(again.scenes_skipped, 2);
  DatasetOptions other = tinyOptions();
  other.size = 96;
  try {
    generateDataset(dir, other);
    ADD_FAILURE() << "a dataset with other options was extended";
  } catch (const InvalidArgumentError& error) {
    EXPECT_NE(std::string(error.what()).find("size"), std::string::npos) << error.what();
  }
  // Without validation every scene is for training, and the manifest says so.
  DatasetOptions all_training = tinyOptions();
  all_training.scenes = 1;
  all_training.frames = 2;
  all_training.validation_fraction = 0.0;
  generateDataset(dir + "_all_training", all_training);
  EXPECT_EQ(readJson(fs::path(dir + "_all_training") / "dataset.json").at("validation"),
            "none: every scene is for training");
  const BopDataset all_training_data(dir + "_all_training");  // outlives the loop over its frames
  for (const Frame& frame : all_training_data.frames()) EXPECT_FALSE(frame.validation);
  fs::remove_all(dir + "_all_training");
  // Test seeds are refused.
  DatasetOptions test_seeds = tinyOptions();
  test_seeds.first_seed = kFirstTestSeed - 1;
  EXPECT_THROW(generateDataset(dir + "_test_seeds", test_seeds), InvalidArgumentError);

  // A tampered label fails the audit: a shortest first move taken away, then an occlusion.
  const fs::path labels_path = fs::path(dir) / "train" / "000000" / "scene_labels.json";
  nlohmann::json labels = readJson(labels_path);
  const nlohmann::json untouched = labels;
  for (auto& [key, label] : labels.items()) {
    if (!label.contains("shortest_first_moves")) continue;
    std::string moves = label["shortest_first_moves"].get<std::string>();
    moves[moves.find('1')] = '0';
    label["shortest_first_moves"] = moves;
  }
  std::ofstream(labels_path) << labels.dump();
  EXPECT_GT(auditDataset(dir, 24).failures, 0);
  labels = untouched;
  for (auto& [key, label] : labels.items())
    label["occlusion_px"] = label["occlusion_px"].get<int>() + 1;
  std::ofstream(labels_path) << labels.dump();
  EXPECT_GT(auditDataset(dir, 24).failures, 0);
  fs::remove_all(dir);
}

// --randomize: a tiny set whose frames come through the drawn sensors at the drawn cameras; the
// labels name world, sensor and camera, scene_camera's K is the drawn one, and the audit
// re-renders it with the same draws (and catches a changed frame).
TEST(DatasetTest, RandomizedSetNamesItsDrawsAndPassesTheAudit) {
  const fs::path dir = temporaryDir("occlusion_env_randomized");
  DatasetOptions options = quickOptions(4, 3);
  options.randomize = true;
  generateDataset(dir.string(), options);
  const nlohmann::json manifest = readJson(dir / "dataset.json");
  EXPECT_EQ(manifest.at("options").at("randomize"), true);
  EXPECT_FALSE(manifest.at("options").contains("world"));  // unset: drawn
  EXPECT_TRUE(manifest.at("options").contains("camera_randomization"));
  std::set<std::string> sensors;
  for (int scene = 0; scene < options.scenes; ++scene) {
    const fs::path folder = dir / "train" / idName(scene);
    const nlohmann::json labels = readJson(folder / "scene_labels.json");
    const nlohmann::json camera = readJson(folder / "scene_camera.json");
    for (const auto& [key, label] : labels.items()) {
      const std::string world = label.at("world"), sensor = label.at("depth_sensor");
      EXPECT_TRUE(world == "void" || world == "room") << world;
      sensors.insert(sensor);
      const nlohmann::json& drawn = label.at("camera");
      EXPECT_GE(drawn.at("radius_m").get<double>(), 0.5);
      EXPECT_LE(drawn.at("radius_m").get<double>(), 1.5);
      EXPECT_EQ(camera.at(key).at("cam_K").at(0), drawn.at("fx"));
      EXPECT_EQ(camera.at(key).at("cam_K").at(2), drawn.at("cx"));
      EXPECT_EQ(camera.at(key).at("scene_scale"), drawn.at("scene_scale"));
      const cv::Mat rgb = cv::imread((folder / "rgb" / (idName(std::stoi(key)) + ".png")).string());
      EXPECT_EQ(rgb.cols, drawn.at("width").get<int>());
    }
  }
  EXPECT_GE(sensors.size(), 2u);  // seeds 0..3 draw realsense_d435, azure_kinect, ideal, ...
  // The reader gives each frame its drawn camera's intrinsics.
  const BopDataset randomized(dir.string());
  for (const Frame& frame : randomized.frames()) {
    const nlohmann::json drawn = readJson(fs::path(frame.scene_folder) / "scene_labels.json")
                                     .at(std::to_string(frame.labels.image_id))
                                     .at("camera");
    EXPECT_EQ(frame.intrinsics.fx, drawn.at("fx").get<double>());
    EXPECT_EQ(frame.intrinsics.fy, drawn.at("fy").get<double>());
    EXPECT_EQ(frame.intrinsics.cx, drawn.at("cx").get<double>());
    EXPECT_EQ(frame.intrinsics.cy, drawn.at("cy").get<double>());
    EXPECT_EQ(frame.intrinsics.width, drawn.at("width").get<int>());
    EXPECT_EQ(frame.intrinsics.height, drawn.at("height").get<int>());
  }
  const AuditReport audit = auditDataset(dir.string(), 12);
  EXPECT_EQ(audit.frames_checked, 12);
  EXPECT_EQ(audit.failures, 0) << (audit.problems.empty() ? "" : audit.problems.front());

  // Test seeds stay refused.
  DatasetOptions test_seeds = options;
  test_seeds.first_seed = kFirstTestSeed;
  EXPECT_THROW(generateDataset(dir.string() + "_test", test_seeds), InvalidArgumentError);

  // A frame one level brighter fails the audit.
  const fs::path rgb_path = dir / "train" / idName(2) / "rgb" / (idName(2) + ".png");
  cv::Mat rgb = cv::imread(rgb_path.string());
  rgb.at<cv::Vec3b>(rgb.rows / 2, rgb.cols / 2)[0] ^= 1;
  cv::imwrite(rgb_path.string(), rgb);
  EXPECT_GT(auditDataset(dir.string(), 12).failures, 0);
  fs::remove_all(dir);
}

TEST(DatasetTest, FirstElevationIsDrawnPerSceneOverTheSameScenesAndPassesTheAudit) {
  const fs::path dir = temporaryDir("occlusion_env_elevated");
  DatasetOptions options = tinyOptions();
  options.scenes = 4;
  options.frames = 3;
  options.oracle_labels = false;
  options.first_elevation_min_rad = 0.6;
  options.first_elevation_max_rad = 1.2;
  generateDataset(dir.string(), options);
  const nlohmann::json manifest = readJson(dir / "dataset.json");
  EXPECT_EQ(manifest.at("options").at("first_elevation_min_rad"), 0.6);
  std::set<double> first_elevations;
  for (int scene = 0; scene < options.scenes; ++scene) {
    const nlohmann::json labels = readJson(dir / "train" / idName(scene) / "scene_labels.json");
    const double first = labels.at("0").at("elevation_rad").get<double>();
    EXPECT_GE(first, 0.6);
    EXPECT_LT(first, 1.2);
    first_elevations.insert(first);
  }
  EXPECT_EQ(first_elevations.size(), 4u);  // drawn per scene
  // The scene's start view stays where it was drawn: frame 0 keeps the plain set's azimuth.
  const fs::path plain_dir = dir.string() + "_plain";
  DatasetOptions plain_options = options;
  plain_options.first_elevation_min_rad = plain_options.first_elevation_max_rad = 0.0;
  generateDataset(plain_dir.string(), plain_options);
  for (int scene = 0; scene < options.scenes; ++scene) {
    const nlohmann::json plain =
        readJson(plain_dir / "train" / idName(scene) / "scene_labels.json");
    const nlohmann::json raised = readJson(dir / "train" / idName(scene) / "scene_labels.json");
    EXPECT_EQ(plain.at("0").at("elevation_rad").get<double>(), 0.0);
    EXPECT_EQ(raised.at("0").at("azimuth_rad"), plain.at("0").at("azimuth_rad"));
  }
  const AuditReport audit = auditDataset(dir.string(), 12);
  EXPECT_EQ(audit.failures, 0) << (audit.problems.empty() ? "" : audit.problems.front());
  // A range upside down is refused.
  options.first_elevation_min_rad = 1.3;
  EXPECT_THROW(generateDataset(dir.string() + "_bad", options), InvalidArgumentError);
  fs::remove_all(dir);
  fs::remove_all(plain_dir);
}

TEST(DatasetTest, MaxSceneAttemptsReachesTheEnvironmentAndTheManifestOnlyWhenSet) {
  DatasetOptions options = tinyOptions();
  EXPECT_EQ(options.max_scene_attempts, EnvironmentOptions().max_scene_attempts);
  EXPECT_FALSE(options.definingJson().contains("max_scene_attempts"));  // old sets keep theirs
  options.max_scene_attempts = 60;  // a seed whose scene needs more draws than the default
  EXPECT_EQ(options.definingJson().at("max_scene_attempts"), 60);
  EXPECT_EQ(environmentOptionsFor(options).max_scene_attempts, 60);  // the audit's too
  options.max_scene_attempts = 0;
  EXPECT_THROW(options.validate(), InvalidArgumentError);
}

// In a room the far walls stand up to 12 m from the camera: their depth is stored, not clamped
// at the old unit's 6.55 m, and the set passes its audit. An image that records the old unit
// (0.1 mm) is read with it.
TEST(DatasetTest, ARoomsFarDepthIsStoredAndEachImageIsReadInItsOwnUnit) {
  const fs::path dir = temporaryDir("occlusion_env_room_depth");
  DatasetOptions options = quickOptions(2, 2);
  options.world = "room";
  generateDataset(dir.string(), options);
  const BopDataset room(dir.string());
  float farthest = 0.0f;
  for (const Frame& frame : room.frames()) {
    EXPECT_EQ(frame.depth_scale_mm, kDepthScaleMm);
    const cv::Mat depth = room.readDepthMeters(frame);
    for (auto it = depth.begin<float>(); it != depth.end<float>(); ++it) {
      if (std::isfinite(*it)) farthest = std::max(farthest, *it);
    }
  }
  EXPECT_GT(farthest, 6.6f);  // beyond 65535 units of 0.1 mm
  const AuditReport audit = auditDataset(dir.string(), 4);
  EXPECT_EQ(audit.failures, 0) << (audit.problems.empty() ? "" : audit.problems.front());

  // The first frame rewritten in units of 0.1 mm, as sets were before, and recorded so.
  const Frame& first = room.frames().front();
  const cv::Mat metres = room.readDepthMeters(first);
  cv::Mat old_units(metres.size(), CV_16UC1);
  for (int row = 0; row < metres.rows; ++row) {
    for (int col = 0; col < metres.cols; ++col) {
      const float m = metres.at<float>(row, col);
      old_units.at<std::uint16_t>(row, col) =
          std::isfinite(m)
              ? static_cast<std::uint16_t>(std::min(65535.0, std::round(m * 1000.0 / 0.1)))
              : 0;
    }
  }
  cv::imwrite(first.depth_path, old_units);
  const fs::path camera_path = fs::path(first.scene_folder) / "scene_camera.json";
  nlohmann::json cameras = readJson(camera_path);
  cameras[std::to_string(first.labels.image_id)]["depth_scale"] = 0.1;
  std::ofstream(camera_path) << cameras.dump();
  const BopDataset reread(dir.string());
  for (const Frame& frame : reread.frames()) {
    if (frame.depth_path != first.depth_path) continue;
    EXPECT_EQ(frame.depth_scale_mm, 0.1);
    const cv::Mat back = reread.readDepthMeters(frame);
    for (int row = 0; row < back.rows; ++row) {
      for (int col = 0; col < back.cols; ++col) {
        const float m = metres.at<float>(row, col), b = back.at<float>(row, col);
        ASSERT_EQ(std::isfinite(m), std::isfinite(b));
        if (std::isfinite(m)) EXPECT_NEAR(b, std::min(m, 6.5535f), 0.06e-3) << row << "," << col;
      }
    }
  }
  fs::remove_all(dir);
}

// --randomize with the camera's ranges given: a camera pinned to 60 deg, the full size and no
// jitter, at 1 m, draws exactly that camera; the manifest records the ranges and the audit
// re-draws them. Ranges without --randomize, or a min above its max, are refused.
TEST(DatasetTest, CameraRangesReachTheDrawsTheManifestAndTheAudit) {
  const fs::path dir = temporaryDir("occlusion_env_camera_ranges");
  DatasetOptions options = quickOptions(3, 2);
  options.randomize = true;
  options.camera_ranges.radius_range_m = {1.0, 1.0};
  options.camera_ranges.field_of_view_range_rad = {M_PI / 3.0, M_PI / 3.0};
  options.camera_ranges.resolution_scale_range = {1.0, 1.0};
  options.camera_ranges.focal_length_jitter = 0.0;
  options.camera_ranges.principal_point_jitter = 0.0;
  generateDataset(dir.string(), options);
  const nlohmann::json recorded =
      readJson(dir / "dataset.json").at("options").at("camera_randomization");
  EXPECT_EQ(recorded.at("radius_range"), nlohmann::json({1.0, 1.0}));
  EXPECT_EQ(recorded.at("principal_point_jitter"), 0.0);
  const double fx = options.size / 2.0 / std::tan(M_PI / 6.0);
  const BopDataset pinned(dir.string());
  ASSERT_EQ(pinned.frames().size(), 6u);
  for (const Frame& frame : pinned.frames()) {
    ASSERT_TRUE(frame.labels.setup.has_value());
    EXPECT_DOUBLE_EQ(frame.labels.setup->radius_m, 1.0);
    EXPECT_DOUBLE_EQ(frame.labels.setup->field_of_view_rad, M_PI / 3.0);
    EXPECT_EQ(frame.intrinsics.width, options.size);
    EXPECT_NEAR(frame.intrinsics.fx, fx, 1e-9);
    EXPECT_NEAR(frame.intrinsics.cx, (options.size - 1) / 2.0, 1e-9);
  }
  const AuditReport audit = auditDataset(dir.string(), 6);
  EXPECT_EQ(audit.failures, 0) << (audit.problems.empty() ? "" : audit.problems.front());
  fs::remove_all(dir);

  DatasetOptions not_drawn = tinyOptions();
  not_drawn.camera_ranges.focal_length_jitter = 0.0;
  EXPECT_THROW(not_drawn.validate(), InvalidArgumentError);
  DatasetOptions reversed = options;
  reversed.camera_ranges.radius_range_m = {1.5, 0.5};
  EXPECT_THROW(reversed.validate(), InvalidArgumentError);
  // Unset, a set's options are those recorded before the ranges were options.
  EXPECT_EQ(tinyOptions().definingJson().contains("radius_range"), false);
  DatasetOptions defaults = tinyOptions();
  defaults.randomize = true;
  EXPECT_EQ(defaults.definingJson().at("camera_randomization").at("resolution_scale_range"),
            nlohmann::json({0.5, 1.0}));
}

}  // namespace
}  // namespace dataset
}  // namespace occlusion_env
