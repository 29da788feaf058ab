// occlusion_render: renders one scene of the environment and writes its images as PNG files.
//   occlusion_render --seed 7 --out /tmp/scene7
//   occlusion_render --source sweethome3d --preset two_chairs --azimuth 0.05
//   occlusion_render --source sweethome3d --list
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/render/visualization.hpp"
#include "occlusion_env/tools/cli_options.hpp"

namespace {

/// The tool's own options; the scene's come from environmentOptionTable().
struct Arguments {
  occlusion_env::EnvironmentOptions options;
  std::uint64_t seed = 0;
  int size = 256;
  std::optional<double> azimuth_rad;    // empty: drawn from the seed
  std::optional<double> elevation_rad;  // empty: the environment's start elevation
  int steps = 0;
  std::vector<double> action{1.0, 0.0};
  std::string out_dir = "occlusion_render_out";
  bool list = false;
};

const occlusion_env::OptionTable<Arguments>& argumentTable() {
  using occlusion_env::OptionSpec;
  static const auto table =
      occlusion_env::OptionTable<Arguments>()
          .add("seed", &Arguments::seed, OptionSpec("scene seed"))
          .add("size", &Arguments::size,
               OptionSpec("image width and height").unit("px").range(64, 1024))
          .add("azimuth", &Arguments::azimuth_rad,
               OptionSpec("start azimuth (default: drawn from the seed)").unit("rad"))
          .add("elevation", &Arguments::elevation_rad,
               OptionSpec("start elevation (default: the environment's)").unit("rad"))
          .add("steps", &Arguments::steps,
               OptionSpec("then take this many steps along --action before writing").atLeast(0))
          .add("action", &Arguments::action, OptionSpec("the step direction DAZ,DEL"))
          .add("out", &Arguments::out_dir, OptionSpec("output folder"))
          .add("list", &Arguments::list, OptionSpec("print the catalogue's objects and exit"));
  return table;
}

[[noreturn]] void fail(const std::string& message) {
  std::cerr << "occlusion_render: " << message << "\n(--help lists the options)\n";
  std::exit(2);
}

void writeRgb(const std::filesystem::path& path, const cv::Mat& rgb) {
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  if (!cv::imwrite(path.string(), bgr)) fail("cannot write " + path.string());
}

int run(const Arguments& args) {
  using namespace occlusion_env;
  if (args.list) {
    const auto catalog = makeCatalog(args.options.catalog);
    for (const ObjectInfo& info : catalog->objects()) {
      std::cout << std::left << std::setw(48) << info.id << " " << std::setw(10) << info.category
                << " " << info.name << " (" << info.creator << ", " << info.license << ")\n";
    }
    std::cout << catalog->objects().size() << " objects in " << catalog->categories().size()
              << " categories\n";
    return 0;
  }

  EnvironmentOptions options = args.options;
  options.width = options.height = args.size;
  Environment env(options);
  if (args.action.size() != 2) fail("--action expects DAZ,DEL");
  ResetOptions reset;
  reset.start_azimuth_rad = args.azimuth_rad;
  reset.start_elevation_rad = args.elevation_rad;
  StepResult result = env.reset(args.seed, reset);
  for (int t = 0; t < args.steps && !result.terminated && !result.truncated; ++t) {
    result = env.step({args.action[0], args.action[1]});
    std::cout << std::setprecision(6) << "step " << result.info.step_index << ": reward "
              << result.reward << ", occlusion " << result.info.occlusion.total_pixels << " px"
              << (result.terminated  ? " (terminated)"
                  : result.truncated ? " (truncated)"
                                     : "")
              << "\n";
  }
  const Observation& observation = *result.observation;
  const int num_objects = static_cast<int>(env.scene().objects.size());

  const std::filesystem::path out(args.out_dir);
  std::filesystem::create_directories(out);
  writeRgb(out / "rgb.png", observation.rgb);
  writeRgb(out / "depth.png", colorizeDepth(observation.depth));
  writeRgb(out / "occlusion.png", occlusionOverlay(observation.rgb, observation.amodal_bits,
                                                   observation.occlusion_mask, num_objects));
  writeRgb(out / "instance.png", colorizeInstances(observation.instance));

  const StepInfo& info = result.info;
  std::cout << std::fixed << std::setprecision(4) << "seed " << args.seed << ", preset "
            << args.options.preset << ", world " << args.options.world.world << ", depth sensor "
            << args.options.sensor.depth_sensor << ", camera azimuth " << info.pose.azimuth_rad
            << " rad, elevation " << info.pose.elevation_rad << " rad\n";
  for (int k = 0; k < num_objects; ++k) {
    const SceneObject& object = env.scene().objects[k];
    std::cout << "  object " << k << ": " << object.model->info.id << " ("
              << object.model->info.name << ", " << object.model->info.category << ", "
              << object.model->render.triangleCount() << " triangles rendered) at ("
              << std::setprecision(3) << object.position_m.x() << ", " << object.position_m.y()
              << ", " << object.position_m.z() << ") m\n";
  }
  std::cout << "occlusion L = " << info.occlusion.total_pixels << " px (Eq. 9), occluded area "
            << info.occlusion.occluded_area_pixels << " px, silhouette union "
            << info.occlusion.union_pixels << " px\n";
  for (const PairOcclusion& pair : info.occlusion.pairs) {
    std::cout << "  pair (" << pair.first << ", " << pair.second << "): " << pair.pixels << " px\n";
  }
  std::cout << "wrote " << (out / "rgb.png").string()
            << ", depth.png, occlusion.png, instance.png\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  Arguments args;
  CLI::App app(
      "Renders the start view of one seeded scene and writes rgb.png, depth.png (colourised),\n"
      "occlusion.png (overlay: occluded pixels red, each object's amodal outline) and "
      "instance.png.",
      "occlusion_render");
  tools::addOptionFlags(app, argumentTable(), args);
  tools::addOptionFlags(
      app, environmentOptionTable(), args.options,
      {"preset", "catalog_source", "catalog_paths", "categories", "object_ids", "num_objects",
       "lod_triangle_budget", "world", "clutter", "depth_sensor", "sensor_parameters"});
  if (const int exit_code = tools::parseCommandLine(app, argc, argv); exit_code >= 0) {
    return exit_code;
  }
  try {
    return run(args);
  } catch (const std::exception& error) {
    std::cerr << "occlusion_render: " << error.what() << "\n";
    return 1;
  }
}
