#include "occlusion_env/dataset/generator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/random.hpp"
#include "occlusion_env/common/workers.hpp"
#include "occlusion_env/dataset/bop_dataset.hpp"
#include "occlusion_env/dataset/scene_writer.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/occlusion/occlusion.hpp"
#include "occlusion_env/occlusion/occlusion_gradient.hpp"

namespace occlusion_env {
namespace dataset {
namespace {

namespace fs = std::filesystem;

constexpr int kFormatVersion = 1;
constexpr std::uint64_t kMoveStreamSalt = 0x6d6f7665736d6f76ull;  // the moves' own random stream
constexpr std::uint64_t kFirstElevationSalt = 0x6669727374656c65ull;  // frame 0's elevation

std::string spaceLeft(const fs::path& path) {
  std::error_code error;
  const fs::space_info space = fs::space(path, error);
  if (error) return "unknown";
  return std::to_string(space.available / (1024 * 1024)) + " MiB";
}

[[noreturn]] void writeFailed(const fs::path& path) {
  throw std::runtime_error("dataset: cannot write " + path.string() +
                           " (disk full? space left: " + spaceLeft(path.parent_path()) + ")");
}

void writePng(const fs::path& path, const cv::Mat& image) {
  if (!cv::imwrite(path.string(), image)) writeFailed(path);
}

// Written to a temporary name, then renamed: a file that exists is complete.
void writeJsonFile(const fs::path& path, const nlohmann::json& json) {
  const fs::path temporary = path.string() + ".tmp";
  {
    std::ofstream out(temporary);
    out << json.dump(1) << '\n';
    if (!out) writeFailed(temporary);
  }
  std::error_code error;
  fs::rename(temporary, path, error);
  if (error) writeFailed(path);
}

nlohmann::json rowMajor(const Eigen::Matrix3d& matrix) {
  nlohmann::json values = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) values.push_back(matrix(r, c));
  }
  return values;
}

nlohmann::json millimetres(const Eigen::Vector3d& metres) {
  return {1000.0 * metres.x(), 1000.0 * metres.y(), 1000.0 * metres.z()};
}

nlohmann::json boundingBox(const cv::Mat& mask) {
  if (cv::countNonZero(mask) == 0) return {-1, -1, -1, -1};
  const cv::Rect box = cv::boundingRect(mask);
  return {box.x, box.y, box.width, box.height};
}

/// A string option of a manifest, unset where it is null or missing (manifests from before it).
std::optional<std::string> optionalString(const nlohmann::json& defining, const char* key) {
  if (!defining.contains(key) || defining.at(key).is_null()) return std::nullopt;
  return defining.at(key).get<std::string>();
}

EnvironmentOptions environmentOptionsOf(const nlohmann::json& defining) {
  EnvironmentOptions options;
  applySceneRandomization(options, optionalString(defining, "world"),
                          optionalString(defining, "depth_sensor"),
                          defining.value("randomize", false));
  options.width = options.height = defining.at("size").get<int>();
  options.catalog.source = defining.at("source").get<std::string>();
  options.catalog.paths = defining.at("catalog_paths").get<std::vector<std::string>>();
  options.scene.categories = defining.at("categories").get<std::vector<std::string>>();
  options.scene.num_objects = defining.at("num_objects").get<int>();
  options.scene.model_split = parseModelSplit(defining.at("model_split").get<std::string>());
  options.max_scene_attempts = defining.value("max_scene_attempts", options.max_scene_attempts);
  if (defining.contains("camera_randomization")) {
    environmentOptionTable().applyJson(defining.at("camera_randomization"), options);
  }
  return options;
}

// One worker: an environment (its GL context on the worker's thread) and what labels need.
struct Worker {
  Worker(const EnvironmentOptions& options, std::shared_ptr<ObjectLibrary> library)
      : environment(options, std::move(library)), gradient(options.gradient), oracle(environment) {}
  Environment environment;
  AnalyticOcclusionGradient gradient;
  OcclusionOracle oracle;
  cv::Mat bgr, depth16, occlusion;
  double oracle_seconds = 0.0;  // spent in the labels' oracle queries
};

// The labels of the view `buffers` show at `pose`, before the oracle (which renders elsewhere).
FrameLabels viewLabels(Worker& worker, const RenderBuffers& buffers, const SphericalPose& pose,
                       int image_id, cv::Mat& occlusion_mask) {
  Environment& environment = worker.environment;
  const int num_objects = environment.numObjects();
  FrameLabels labels;
  labels.image_id = image_id;
  labels.pose = pose;
  labels.occlusion_px =
      computeOcclusion(buffers.amodal_bits, num_objects, &occlusion_mask).total_pixels;
  const GradientResult gradient = worker.gradient.compute(
      buffers, num_objects, environment.intrinsics(), environment.camera(), pose);
  labels.smooth_loss_px = gradient.loss;
  labels.gradient_azimuth = gradient.gradient.x();
  labels.gradient_elevation = gradient.gradient.y();
  labels.gradient_valid = gradient.valid;
  if (gradient.valid) labels.descent = directionOf(-gradient.gradient.x(), -gradient.gradient.y());
  return labels;
}

void addOracleLabels(Worker& worker, FrameLabels& labels) {
  const auto start = std::chrono::steady_clock::now();
  const OracleAnswer answer = worker.oracle.query(labels.pose);
  labels.has_oracle = true;
  labels.oracle_steps = answer.steps;
  if (!answer.path.empty()) {
    labels.escape =
        directionOf(answer.path.front().d_azimuth_rad, answer.path.front().d_elevation_rad);
  }
  labels.shortest_first_moves = worker.oracle.shortestFirstMoves(labels.pose, answer);
  worker.oracle_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The pose of every frame of a scene: the start view, then a random walk.
std::vector<SphericalPose> framePoses(const Environment& environment, const SphericalPose& start,
                                      std::uint64_t seed, const DatasetOptions& options) {
  RandomSource moves(seed ^ kMoveStreamSalt);
  const double step = environment.options().step_size_rad;
  SphericalPose first = start;
  if (options.first_elevation_max_rad > 0.0 || options.first_elevation_min_rad < 0.0) {
    RandomSource elevation(seed ^ kFirstElevationSalt);
    first = environment.camera().moved(
        start, 0.0,
        elevation.uniform(options.first_elevation_min_rad, options.first_elevation_max_rad) -
            start.elevation_rad);
  }
  std::vector<SphericalPose> poses = {first};
  while (static_cast<int>(poses.size()) < options.frames) {
    const double direction = moves.uniform(0.0, 2.0 * M_PI);
    const int steps =
        1 + static_cast<int>(moves.below(static_cast<std::uint64_t>(options.max_move_steps)));
    poses.push_back(environment.camera().moved(poses.back(), steps * step * std::cos(direction),
                                               steps * step * std::sin(direction)));
  }
  return poses;
}

// The frame's colour and depth as PNGs: what the sensor gives (the observation).
void writeFrameImages(Worker& worker, const fs::path& folder, const std::string& name,
                      const Observation& seen) {
  cv::cvtColor(seen.rgb, worker.bgr, cv::COLOR_RGB2BGR);
  writePng(folder / "rgb" / (name + ".png"), worker.bgr);
  worker.depth16.create(seen.depth.size(), CV_16UC1);
  for (int row = 0; row < seen.depth.rows; ++row) {
    const float* in = seen.depth.ptr<float>(row);
    std::uint16_t* out = worker.depth16.ptr<std::uint16_t>(row);
    for (int col = 0; col < seen.depth.cols; ++col) {
      const double units = std::round(in[col] * 1000.0 / kDepthScaleMm);
      out[col] =
          std::isfinite(in[col]) ? static_cast<std::uint16_t>(std::clamp(units, 1.0, 65535.0)) : 0;
    }
  }
  writePng(folder / "depth" / (name + ".png"), worker.depth16);
}

// The BOP ground truth of one frame: per object its pose, masks and their counts.
void writeObjects(const Environment& environment, const fs::path& folder, const std::string& name,
                  const Eigen::Isometry3d& optical_from_world, nlohmann::json& gt,
                  nlohmann::json& info) {
  const RenderBuffers& buffers = environment.renderBuffers();
  const Scene& scene = environment.scene();
  gt = nlohmann::json::array();
  info = nlohmann::json::array();
  for (int object = 0; object < environment.numObjects(); ++object) {
    // A scaled scene (camera randomisation): the pose of the model scaled by scene_scale.
    const Eigen::Isometry3d optical_from_object =
        optical_from_world * Eigen::Translation3d(scene.scale * scene.objects[object].position_m);
    gt.push_back({{"cam_R_m2c", rowMajor(optical_from_object.linear())},
                  {"cam_t_m2c", millimetres(optical_from_object.translation())},
                  {"obj_id", object + 1}});
    const cv::Mat amodal = (buffers.amodal_bits & (1 << object)) != 0;
    const cv::Mat visible = buffers.instance == (object + 1);
    const std::string mask_name = name + "_" + idName(object) + ".png";
    writePng(folder / "mask" / mask_name, amodal);
    writePng(folder / "mask_visib" / mask_name, visible);
    const int all = cv::countNonZero(amodal), visible_count = cv::countNonZero(visible);
    info.push_back({{"bbox_obj", boundingBox(amodal)},
                    {"bbox_visib", boundingBox(visible)},
                    {"px_count_all", all},
                    {"px_count_valid", all},  // depth is valid wherever something is hit
                    {"px_count_visib", visible_count},
                    {"visib_fract", all > 0 ? static_cast<double>(visible_count) / all : 0.0}});
  }
}

nlohmann::json cameraEntry(const Environment& environment,
                           const Eigen::Isometry3d& optical_from_world) {
  const CameraIntrinsics& k = environment.intrinsics();
  const Eigen::Matrix3d camera_matrix =
      (Eigen::Matrix3d() << k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0).finished();
  nlohmann::json entry = {{"cam_K", rowMajor(camera_matrix)},
                          {"depth_scale", kDepthScaleMm},
                          {"cam_R_w2c", rowMajor(optical_from_world.linear())},
                          {"cam_t_w2c", millimetres(optical_from_world.translation())}};
  const double scale = environment.scene().scale;
  if (scale != 1.0) entry["scene_scale"] = scale;  // world metres per model metre
  return entry;
}

// Frame k of a scene: the view at its pose through the sensor, in frame order (the sensor's
// noise follows its episode stream), so an audit replays frames 0..k to see it again.
// `given_poses`: the frames' poses (SceneWriter); nullptr: the random walk of framePoses().
void writeScene(Worker& worker, const std::string& dir, int index, std::uint64_t seed,
                const DatasetOptions& options,
                const std::vector<SphericalPose>* given_poses = nullptr) {
  Environment& environment = worker.environment;
  const StepResult start = environment.reset(seed);
  const fs::path folder = sceneFolder(dir, index);
  for (const char* sub : {"rgb", "depth", "mask", "mask_visib", "occlusion"}) {
    fs::create_directories(folder / sub);
  }
  worker.oracle.clear(start.info.pose);
  nlohmann::json scene_camera, scene_gt, scene_gt_info, scene_labels;
  const std::vector<SphericalPose> poses =
      given_poses ? *given_poses : framePoses(environment, start.info.pose, seed, options);
  for (int image = 0; image < static_cast<int>(poses.size()); ++image) {
    const SphericalPose& pose = poses[image];
    environment.viewFrom(pose);  // the truth in renderBuffers(), the sensor's in observation()
    const std::string name = idName(image);
    const std::string key = std::to_string(image);
    writeFrameImages(worker, folder, name, environment.observation());
    const Eigen::Isometry3d optical_from_world =
        environment.camera().worldFromOptical(pose).inverse();
    scene_camera[key] = cameraEntry(environment, optical_from_world);
    writeObjects(environment, folder, name, optical_from_world, scene_gt[key], scene_gt_info[key]);

    FrameLabels labels =
        viewLabels(worker, environment.renderBuffers(), pose, image, worker.occlusion);
    labels.setup = environment.sceneSetup();
    writePng(folder / "occlusion" / (name + ".png"), worker.occlusion);
    if (options.oracle_labels) addOracleLabels(worker, labels);  // renders elsewhere: last
    scene_labels[key] = toJson(labels);
  }
  writeJsonFile(folder / "scene_camera.json", scene_camera);
  writeJsonFile(folder / "scene_gt.json", scene_gt);
  writeJsonFile(folder / "scene_gt_info.json", scene_gt_info);
  writeJsonFile(folder / kLabelsFile, scene_labels);  // last: the scene is complete
}

nlohmann::json manifestFor(const DatasetOptions& options, const ObjectCatalog& catalog) {
  nlohmann::json scenes = nlohmann::json::array();
  const int every =
      options.validation_fraction > 0.0
          ? std::max(1, static_cast<int>(std::lround(1.0 / options.validation_fraction)))
          : 0;
  for (int index = 0; index < options.scenes; ++index) {
    const bool validation = every > 0 && index % every == every - 1;
    scenes.push_back({{"index", index},
                      {"seed", options.first_seed + static_cast<std::uint64_t>(index)},
                      {"split", validation ? "val" : "train"}});
  }
  std::vector<std::string> train_models, test_models;
  for (const ObjectInfo& info : catalog.objects()) {
    if (!options.categories.empty() &&
        std::find(options.categories.begin(), options.categories.end(), info.category) ==
            options.categories.end()) {
      continue;
    }
    (modelSplitOf(catalog, info.id) == ModelSplit::kTrain ? train_models : test_models)
        .push_back(info.id);
  }
  return {
      {"tool", "occlusion_dataset"},
      {"format_version", kFormatVersion},
      {"format", "BOP (scene folders under train/), plus occlusion/ and scene_labels.json"},
      {"options", options.definingJson()},
      {"depth_scale_mm", kDepthScaleMm},
      {"direction_convention",
       "theta = atan2(d_elevation, d_azimuth) [rad], 0 = +azimuth, pi/2 = up; stored as "
       "(sin, cos); a horizontal image flip maps (sin, cos) to (sin, -cos)"},
      {"frame_moves",
       "frame 0: the scene's start view (with first_elevation_min/max: at an elevation drawn "
       "uniformly in that range from the scene's seed); each next frame: 1..max_move_steps "
       "steps (uniform) "
       "of step_size in one direction ~ U[0, 2 pi) from the previous frame (elevation clamped)"},
      {"model_split",
       {{"split", "train"}, {"train_models", train_models}, {"test_models_excluded", test_models}}},
      {"validation", every > 0 ? "whole scenes: those with index % " + std::to_string(every) +
                                     " == " + std::to_string(every - 1) + " (one in " +
                                     std::to_string(every) + ")"
                               : std::string("none: every scene is for training")},
      {"scenes", scenes}};
}

}  // namespace

const OptionTable<DatasetOptions>& datasetOptionTable() {
  using O = DatasetOptions;
  static const auto table = [] {
    OptionTable<O> options;
    options.add("scenes", &O::scenes, OptionSpec("number of scenes (N_s)").range(1, 1000000))
        .add("frames", &O::frames, OptionSpec("frames per scene (N_i)").range(1, 100000))
        .add("first_seed", &O::first_seed,
             OptionSpec("scene seeds first_seed .. first_seed + scenes - 1 (training seeds)"))
        .add("size", &O::size, OptionSpec("image width and height").unit("px").range(64, 1024))
        .add("source", &O::source,
             OptionSpec("object catalogue").choices({"embedded", "sweethome3d", "folder"}))
        .add("catalog_paths", &O::catalog_paths,
             OptionSpec("a .sh3f file or folder (sweethome3d), the root (folder)")
                 .flag("--path")
                 .repeatable())
        .add("categories", &O::categories,
             OptionSpec("draw objects of these categories only (empty: any)")
                 .flag("--category")
                 .repeatable())
        .add("num_objects", &O::num_objects,
             OptionSpec("objects per scene").range(2, kMaxSceneObjects).flag("--objects"))
        .add("max_move_steps", &O::max_move_steps,
             OptionSpec("longest move between frames, in steps").range(1, 100))
        .add("first_elevation_min_rad", &O::first_elevation_min_rad,
             OptionSpec("frame 0's elevation is drawn per scene in [this, first-elevation-max]; "
                        "the scene is still drawn at its start view")
                 .unit("rad")
                 .range(-M_PI / 2.0, M_PI / 2.0)
                 .flag("--first-elevation-min"))
        .add("first_elevation_max_rad", &O::first_elevation_max_rad,
             OptionSpec("see first-elevation-min; 0 and 0: frame 0 is the start view")
                 .unit("rad")
                 .range(-M_PI / 2.0, M_PI / 2.0)
                 .flag("--first-elevation-max"))
        .add("max_scene_attempts", &O::max_scene_attempts,
             OptionSpec("draws of a seed's scene until its start view shows occlusion; a seed "
                        "that needs more stops the run")
                 .range(1, 100000))
        .add("oracle_labels", &O::oracle_labels,
             OptionSpec("the oracle's labels (leaving them out is much faster)")
                 .negatedFlag("--no-oracle"));
    addSceneRandomizationOptions(options, &O::world, &O::depth_sensor, &O::randomize);
    addCameraRandomizationRanges(
        options, [](O& o) -> CameraRandomization& { return o.camera_ranges; },
        "with --randomize: ");
    options
        .add("validation_fraction", &O::validation_fraction,
             OptionSpec("fraction of whole scenes for validation")
                 .range(0, 0.5)
                 .flag("--validation"))
        .add("threads", &O::threads,
             OptionSpec("worker threads, one environment each").range(1, 64));
    return options;
  }();
  return table;
}

nlohmann::json DatasetOptions::definingJson() const {
  nlohmann::json json = datasetOptionTable().toJson(*this);
  json.erase("scenes");  // a dataset may grow
  json.erase("threads");
  json["model_split"] = "train";
  json["step_size_rad"] = EnvironmentOptions().step_size_rad;
  // At their defaults the world and sensor options are left out: a default set's options are
  // those recorded before they existed (resumes, and occlusion_train --check's "the model's own
  // data" test, compare them whole).
  if (!world) json.erase("world");
  if (!depth_sensor) json.erase("depth_sensor");
  if (!randomize) json.erase("randomize");
  // Left out at their defaults: a set made before they existed keeps its options.
  if (max_scene_attempts == EnvironmentOptions().max_scene_attempts) {
    json.erase("max_scene_attempts");
  }
  if (first_elevation_min_rad == 0.0 && first_elevation_max_rad == 0.0) {
    json.erase("first_elevation_min_rad");
    json.erase("first_elevation_max_rad");
  }
  // The camera's ranges under one key, and only where they are drawn.
  nlohmann::json ranges = nlohmann::json::object();
  for (const std::string& key : cameraRangeTable().keys()) {
    ranges[key] = json.at(key);
    json.erase(key);
  }
  if (randomize) json["camera_randomization"] = ranges;
  return json;
}

void DatasetOptions::validate() const {
  datasetOptionTable().check(*this);
  requireCameraRangesDrawn(camera_ranges, randomize);
  if (first_elevation_min_rad > first_elevation_max_rad) {
    throw InvalidArgumentError("first_elevation_min (" + std::to_string(first_elevation_min_rad) +
                               ") must not exceed first_elevation_max (" +
                               std::to_string(first_elevation_max_rad) + ")");
  }
  if (first_seed + static_cast<std::uint64_t>(scenes) > kFirstTestSeed) {
    throw InvalidArgumentError(
        "training scenes must use seeds below " + std::to_string(kFirstTestSeed) +
        " (test sets start there); first seed " + std::to_string(first_seed) + " + " +
        std::to_string(scenes) + " scenes reaches into them");
  }
}

namespace {

// Checks one stored frame against the worker's environment, which shows the frame's scene at its
// pose (viewFrom, after the scene's earlier frames), and fresh labels; each difference is a
// problem of `report`.
void auditFrame(Worker& worker, const BopDataset& data, const std::string& dir, const Frame& frame,
                AuditReport& report) {
  const auto problem = [&report, &frame](const std::string& what) {
    ++report.failures;
    if (report.problems.size() < 50) {
      report.problems.push_back("scene " + idName(frame.scene_index) + " image " +
                                idName(frame.labels.image_id) + ": " + what);
    }
  };
  ++report.frames_checked;
  const FrameLabels& stored = frame.labels;
  const RenderBuffers& buffers = worker.environment.renderBuffers();
  const Observation& seen = worker.environment.observation();
  const std::string folder = sceneFolder(dir, frame.scene_index);
  const std::string name = idName(stored.image_id);
  if (stored.setup && !(*stored.setup == worker.environment.sceneSetup())) {
    problem("world, sensor or camera differs");
    return;
  }
  const cv::Mat rgb = data.readRgb(frame);
  if (rgb.size() != seen.rgb.size()) {
    problem("image size differs");
    return;
  }
  if (cv::norm(rgb, seen.rgb, cv::NORM_INF) != 0.0) problem("rgb differs");
  // Against the stored image as it was encoded: its unit, and depths beyond its range clamped.
  const cv::Mat depth = data.readDepthMeters(frame);
  const double unit_m = frame.depth_scale_mm / 1000.0;
  double worst_depth = 0.0;
  bool holes_match = true;
  for (int row = 0; row < depth.rows; ++row) {
    for (int col = 0; col < depth.cols; ++col) {
      const float a = depth.at<float>(row, col), b = seen.depth.at<float>(row, col);
      if (std::isnan(a) != std::isnan(b)) holes_match = false;
      if (!std::isnan(a) && !std::isnan(b)) {
        const double encoded = std::clamp(double(b), unit_m, 65535.0 * unit_m);
        worst_depth = std::max(worst_depth, std::abs(double(a) - encoded));
      }
    }
  }
  if (!holes_match || worst_depth > 0.6 * unit_m) {
    problem("depth differs (worst " + std::to_string(worst_depth) + " m)");
  }
  for (int object = 0; object < worker.environment.numObjects(); ++object) {
    const cv::Mat amodal =
        cv::imread(folder + "/mask/" + name + "_" + idName(object) + ".png", cv::IMREAD_GRAYSCALE);
    const cv::Mat expected = (buffers.amodal_bits & (1 << object)) != 0;
    if (amodal.empty() || cv::norm(amodal, expected, cv::NORM_INF) != 0.0) {
      problem("amodal mask of object " + std::to_string(object) + " differs");
    }
  }
  cv::Mat occlusion;
  FrameLabels labels = viewLabels(worker, buffers, stored.pose, stored.image_id, occlusion);
  if (cv::norm(data.readOcclusionMask(frame), occlusion, cv::NORM_INF) != 0.0) {
    problem("occlusion mask differs");
  }
  if (labels.occlusion_px != stored.occlusion_px) problem("occlusion_px differs");
  const auto close = [](double a, double b) {
    return std::abs(a - b) <= 1e-9 * (1.0 + std::abs(b));
  };
  if (!close(labels.smooth_loss_px, stored.smooth_loss_px) ||
      !close(labels.gradient_azimuth, stored.gradient_azimuth) ||
      !close(labels.gradient_elevation, stored.gradient_elevation) ||
      labels.gradient_valid != stored.gradient_valid) {
    problem("gradient label differs");
  }
  if (stored.has_oracle) {
    addOracleLabels(worker, labels);
    const bool same_escape =
        labels.escape.has_value() == stored.escape.has_value() &&
        (!labels.escape || close(labels.escape->angle_rad, stored.escape->angle_rad)) &&
        (stored.shortest_first_moves.empty() ||  // written before they were recorded
         labels.shortest_first_moves == stored.shortest_first_moves);
    if (labels.oracle_steps != stored.oracle_steps || !same_escape) {
      problem("oracle label differs (" + std::to_string(labels.oracle_steps) + " vs " +
              std::to_string(stored.oracle_steps) + " steps)");
    }
  }
}

}  // namespace

// The writer's pieces for other ways of choosing frames (dataset/scene_writer.hpp).
struct SceneWriter::Impl {
  Impl(const EnvironmentOptions& options, std::shared_ptr<ObjectLibrary> library)
      : worker(options, std::move(library)) {}
  Worker worker;
};

SceneWriter::SceneWriter(const EnvironmentOptions& options, std::shared_ptr<ObjectLibrary> library)
    : impl_(std::make_unique<Impl>(options, std::move(library))) {}
SceneWriter::~SceneWriter() = default;
Environment& SceneWriter::environment() {
  return impl_->worker.environment;
}
OcclusionOracle& SceneWriter::oracle() {
  return impl_->worker.oracle;
}
double SceneWriter::oracleSeconds() const {
  return impl_->worker.oracle_seconds;
}

void SceneWriter::writeScene(const std::string& dir, int index, std::uint64_t seed,
                             const std::vector<SphericalPose>& poses,
                             const DatasetOptions& options) {
  if (poses.empty()) throw InvalidArgumentError("dataset: a scene needs at least one frame");
  dataset::writeScene(impl_->worker, dir, index, seed, options, &poses);
}

EnvironmentOptions environmentOptionsFor(const DatasetOptions& options) {
  return environmentOptionsOf(options.definingJson());
}

nlohmann::json datasetManifest(const DatasetOptions& options, const ObjectCatalog& catalog) {
  return manifestFor(options, catalog);
}

void writeJsonAtomically(const std::string& path, const nlohmann::json& json) {
  writeJsonFile(path, json);
}

void requireResumable(const std::string& dir, const nlohmann::json& defining,
                      const nlohmann::json& defaults) {
  const fs::path manifest_path = fs::path(dir) / kManifestFile;
  if (!fs::exists(manifest_path)) {
    if (fs::exists(dir) && !fs::is_empty(dir)) {
      throw InvalidArgumentError(dir +
                                 " exists and holds no dataset: choose an empty or new folder");
    }
    return;
  }
  std::ifstream in(manifest_path);
  nlohmann::json existing;
  try {
    existing = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    throw InvalidArgumentError(manifest_path.string() +
                               " is not a dataset manifest: " + error.what());
  }
  nlohmann::json theirs = existing.value("options", nlohmann::json::object());
  for (const auto& [key, value] : defaults.items()) {
    if (!theirs.contains(key)) theirs[key] = value;
  }
  std::string differing;
  for (const auto& [key, value] : defining.items()) {
    if (!theirs.contains(key) || theirs.at(key) != value) {
      differing += (differing.empty() ? "" : ", ") + key + " (" +
                   (theirs.contains(key) ? theirs.at(key).dump() : "missing") + " there, " +
                   value.dump() + " here)";
    }
  }
  if (!differing.empty()) {
    throw InvalidArgumentError("the dataset in " + dir + " was made with other options: " +
                               differing + "; use another folder or the same options");
  }
}

GenerationReport generateDataset(const std::string& dir, const DatasetOptions& options,
                                 const ProgressCallback& progress) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  EnvironmentOptions environment_options = environmentOptionsOf(options.definingJson());
  environment_options.validate();
  auto library = std::make_shared<ObjectLibrary>(makeCatalog(environment_options.catalog),
                                                 environment_options.lod_triangle_budget);
  const nlohmann::json manifest = manifestFor(options, library->catalog());
  const fs::path manifest_path = fs::path(dir) / kManifestFile;
  // An option missing from an older manifest is one from before it existed: its default then.
  requireResumable(dir, options.definingJson(), DatasetOptions().definingJson());
  fs::create_directories(fs::path(dir) / kSplitFolder);
  writeJsonFile(manifest_path, manifest);

  std::vector<int> todo;
  GenerationReport report;
  for (int index = 0; index < options.scenes; ++index) {
    if (fs::exists(fs::path(sceneFolder(dir, index)) / kLabelsFile)) {
      ++report.scenes_skipped;
    } else {
      todo.push_back(index);
    }
  }
  std::mutex mutex;  // guards done and progress
  int done = 0;
  runWorkers(options.threads, todo.size(), [&](JobSource& jobs) {
    Worker worker(environment_options, library);
    while (const std::optional<std::size_t> slot = jobs.next()) {
      const int index = todo[*slot];
      writeScene(worker, dir, index, options.first_seed + static_cast<std::uint64_t>(index),
                 options);
      const std::lock_guard<std::mutex> lock(mutex);
      ++done;
      if (progress) progress(done, static_cast<int>(todo.size()));
    }
  });
  report.scenes_written = done;
  report.frames_written = done * options.frames;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

AuditReport auditDataset(const std::string& dir, int samples, std::uint64_t seed) {
  const BopDataset data(dir);
  if (data.frames().empty())
    throw InvalidArgumentError("dataset " + dir + " holds no complete scene");
  const nlohmann::json& defining = data.manifest().at("options");
  if (defining.at("step_size_rad").get<double>() != EnvironmentOptions().step_size_rad) {
    throw InvalidArgumentError("dataset " + dir + " was made with another step size");
  }
  // Frames drawn with their own random source, then grouped by scene (one reset each).
  RandomSource random(seed);
  std::map<int, std::vector<const Frame*>> by_scene;
  const int count = std::min<int>(samples, static_cast<int>(data.frames().size()));
  std::vector<std::size_t> order(data.frames().size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  for (int i = 0; i < count; ++i) {
    const std::size_t j = i + random.below(order.size() - i);
    std::swap(order[i], order[j]);
    const Frame& frame = data.frames()[order[i]];
    by_scene[frame.scene_index].push_back(&frame);
  }
  const EnvironmentOptions options = environmentOptionsOf(defining);
  Worker worker(options, nullptr);
  AuditReport report;
  for (const auto& [scene, frames] : by_scene) {
    const StepResult start = worker.environment.reset(frames.front()->scene_seed);
    worker.oracle.clear(start.info.pose);
    // A sensor's noise follows its episode stream: its frames are replayed in order up to the
    // last sampled one, as they were made. Ideal frames need only their own pose.
    const bool replay = !worker.environment.sensor().isIdeal();
    std::map<int, const Frame*> sampled, all;
    for (const Frame* frame : frames) sampled[frame->labels.image_id] = frame;
    for (const Frame& frame : data.frames()) {
      if (frame.scene_index == scene) all[frame.labels.image_id] = &frame;
    }
    for (const auto& [image_id, frame] : replay ? all : sampled) {
      if (image_id > sampled.rbegin()->first) break;
      worker.environment.viewFrom(frame->labels.pose);
      if (sampled.count(image_id)) auditFrame(worker, data, dir, *frame, report);
    }
  }
  return report;
}

}  // namespace dataset
}  // namespace occlusion_env
