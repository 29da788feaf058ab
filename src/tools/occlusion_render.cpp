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
#include "occlusion_env/tools/arguments.hpp"

namespace {

constexpr const char* kUsage = R"(Usage: occlusion_render [options]
Renders the start view of one seeded scene and writes rgb.png, depth.png (colourised),
occlusion.png (overlay: occluded pixels red, each object's amodal outline) and instance.png.

Options:
  --seed N            scene seed (default 0)
  --preset P          random | two_chairs | two_tables (default random)
  --source S          embedded | sweethome3d | folder (default embedded)
  --path P            a .sh3f file or folder (sweethome3d), the root (folder); repeatable
  --category C        draw objects of this category only; repeatable
  --id ID             use this object; repeat for several (see --list)
  --objects N         number of objects (default 3)
  --size N            image width and height [px] (default 256)
  --azimuth RAD       start azimuth (default: drawn from the seed)
  --elevation RAD     start elevation (default 0)
  --lod N             triangle budget per object, 0 = full meshes (default 5000)
  --steps N           then take N steps along --action before writing (default 0)
  --action DAZ,DEL    the step direction (default 1,0: increasing azimuth)
  --world W           void | room: the objects on a floor inside walls (default void)
  --clutter N         background objects in a room, 0..8 (default 3)
  --depth-sensor S    ideal | kinect_v1 | realsense_d435 | azure_kinect: rgb.png and depth.png
                      as that camera gives them (default ideal)
  --sensor-parameters FILE  sensor parameters (default: built in, = config/sensors.yaml)
  --out DIR           output folder (default ./occlusion_render_out)
  --list              print the catalogue's objects and exit
  --help              this text
)";

struct Arguments {
  occlusion_env::EnvironmentOptions options;
  occlusion_env::ResetOptions reset;
  std::uint64_t seed = 0;
  std::string out_dir = "occlusion_render_out";
  int steps = 0;
  occlusion_env::Action action{1.0, 0.0};
  bool list = false;
};

[[noreturn]] void fail(const std::string& message) {
  std::cerr << "occlusion_render: " << message << "\n(--help lists the options)\n";
  std::exit(2);
}

Arguments parse(int argc, char** argv) {
  namespace tools = occlusion_env::tools;
  constexpr double kHuge = 1e12;
  Arguments args;
  tools::ArgumentReader reader(argc, argv);
  try {
    while (reader.next()) {
      const std::string& flag = reader.flag();
      if (flag == "--help" || flag == "-h") {
        std::cout << kUsage;
        std::exit(0);
      } else if (flag == "--list") {
        args.list = true;
      } else if (flag == "--seed") {
        args.seed = reader.unsignedInteger();
      } else if (flag == "--preset") {
        args.options.preset = reader.text();
      } else if (flag == "--source") {
        args.options.catalog.source = reader.text();
      } else if (flag == "--path") {
        args.options.catalog.paths.push_back(reader.text());
      } else if (flag == "--category") {
        args.options.scene.categories.push_back(reader.text());
      } else if (flag == "--id") {
        args.options.scene.object_ids.push_back(reader.text());
      } else if (flag == "--objects") {
        args.options.scene.num_objects = static_cast<int>(reader.integer(1, 1000));
      } else if (flag == "--size") {
        args.options.width = args.options.height = static_cast<int>(reader.integer(1, 1 << 16));
      } else if (flag == "--azimuth") {
        args.reset.start_azimuth_rad = reader.number(-kHuge, kHuge);
      } else if (flag == "--elevation") {
        args.reset.start_elevation_rad = reader.number(-kHuge, kHuge);
      } else if (flag == "--lod") {
        args.options.lod_triangle_budget = static_cast<std::size_t>(reader.integer(0, 1LL << 40));
      } else if (flag == "--steps") {
        args.steps = static_cast<int>(reader.integer(0, 1'000'000'000));
      } else if (flag == "--action") {
        const std::vector<double> action = reader.numbers(-kHuge, kHuge);
        if (action.size() != 2) fail("--action expects DAZ,DEL");
        args.action = {action[0], action[1]};
      } else if (flag == "--world") {
        args.options.world.world = reader.text();
      } else if (flag == "--clutter") {
        args.options.world.clutter = static_cast<int>(reader.integer(0, 8));
      } else if (flag == "--depth-sensor") {
        args.options.sensor.depth_sensor = reader.text();
      } else if (flag == "--sensor-parameters") {
        args.options.sensor.parameters_file = reader.text();
      } else if (flag == "--out") {
        args.out_dir = reader.text();
      } else {
        reader.unknown();
      }
    }
  } catch (const tools::ArgumentError& error) {
    fail(error.what());
  }
  return args;
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

  Environment env(args.options);
  StepResult result = env.reset(args.seed, args.reset);
  for (int t = 0; t < args.steps && !result.terminated && !result.truncated; ++t) {
    result = env.step(args.action);
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
  const Arguments args = parse(argc, argv);
  try {
    return run(args);
  } catch (const std::exception& error) {
    std::cerr << "occlusion_render: " << error.what() << "\n";
    return 1;
  }
}
