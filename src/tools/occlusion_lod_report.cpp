// occlusion_lod_report: how much of each object's silhouette the level-of-detail meshes keep, for
// several triangle budgets and camera distances. The numbers behind the choice of the default
// budget (BENCHMARKS.md, "LOD budget").
//   occlusion_lod_report                                    (catalogue chairs, default grid)
//   occlusion_lod_report --budgets 4000,5000 --distances 1.6 --per-object
#include <algorithm>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/statistics.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/geometry/camera.hpp"
#include "occlusion_env/render/lod_quality.hpp"
#include "occlusion_env/render/osmesa_renderer.hpp"
#include "occlusion_env/scene/object_library.hpp"
#include "occlusion_env/tools/cli_options.hpp"

namespace {

using occlusion_env::median;
using occlusion_env::OptionSpec;
using occlusion_env::OptionTable;

/// The tool's own options; the catalogue's (source, paths) come from environmentOptionTable().
struct Arguments {
  occlusion_env::EnvironmentOptions environment;
  std::string category = "chair";
  std::vector<double> budgets{3000, 4000, 5000, 6000, 8000};
  std::vector<double> distances{1.0, 1.6, 2.5};
  int size = 256;
  double min_iou = 0.98;
  bool per_object = false;

  Arguments() { environment.catalog.source = "sweethome3d"; }
};

const OptionTable<Arguments>& argumentTable() {
  static const auto table =
      OptionTable<Arguments>()
          .add("category", &Arguments::category,
               OptionSpec("objects of this category (\"\" = all)"))
          .add("budgets", &Arguments::budgets,
               OptionSpec("triangle budgets").unit("triangles").range(1, 1e9))
          .add("distances", &Arguments::distances,
               OptionSpec("camera distances (outside the bounding sphere; the LOD test uses 1.6, "
                          "where the diagonal spans about half of the image)")
                   .unit("object diagonals")
                   .range(0.6, 1e3))
          .add("size", &Arguments::size,
               OptionSpec("image width and height").unit("px").range(1, 1 << 16))
          .add("min_iou", &Arguments::min_iou,
               OptionSpec("the threshold counted against").range(0, 1))
          .add("per_object", &Arguments::per_object,
               OptionSpec("also print each object's worst IoU"));
  return table;
}

/// Every object's worst silhouette IoU per budget and distance, and the triangle counts.
struct Measurements {
  std::vector<std::string> ids;
  std::vector<std::vector<std::vector<double>>> worst;  // [budget][distance][object]
  std::vector<std::size_t> lod_triangles;               // per budget, all objects
  std::size_t full_triangles = 0;
  std::size_t views = 0;
};

std::vector<std::string> objectIds(const occlusion_env::ObjectCatalog& catalog,
                                   const std::string& category) {
  std::vector<std::string> ids;
  if (category.empty()) {
    for (const occlusion_env::ObjectInfo& info : catalog.objects()) ids.push_back(info.id);
  } else {
    ids = catalog.idsInCategory(category);
  }
  if (ids.empty()) throw occlusion_env::CatalogError("no object in category '" + category + "'");
  return ids;
}

Measurements measure(const Arguments& args) {
  using namespace occlusion_env;
  std::shared_ptr<const ObjectCatalog> catalog = makeCatalog(args.environment.catalog);
  Measurements m;
  m.ids = objectIds(*catalog, args.category);
  ObjectLibrary library(catalog, 0);  // full meshes; the budgets are applied here
  auto renderer =
      makeOsMesaRenderer(CameraIntrinsics::fromFieldOfView(args.size, args.size, M_PI / 3.0));
  const std::vector<SphericalPose> views = silhouetteCheckViews();
  m.views = views.size();
  RenderBuffers full_buffers, lod_buffers;
  m.worst.assign(args.budgets.size(), std::vector<std::vector<double>>(args.distances.size()));
  m.lod_triangles.assign(args.budgets.size(), 0);
  for (std::size_t o = 0; o < m.ids.size(); ++o) {
    std::cerr << "\r" << (o + 1) << "/" << m.ids.size() << " " << m.ids[o] << "\x1b[K"
              << std::flush;
    const auto model = library.get(m.ids[o]);
    m.full_triangles += model->full.triangleCount();
    std::ostringstream row;
    row << std::fixed << std::setprecision(4) << std::left << std::setw(44) << m.ids[o]
        << std::right << std::setw(8) << model->full.triangleCount();
    for (std::size_t b = 0; b < args.budgets.size(); ++b) {
      const Mesh lod = simplifyMesh(model->full, static_cast<std::size_t>(args.budgets[b]));
      m.lod_triangles[b] += lod.triangleCount();
      for (std::size_t d = 0; d < args.distances.size(); ++d) {
        const SphericalCamera camera(args.distances[d], 1.3);
        const double iou = worstSilhouetteIou(*renderer, model->full, lod, camera, views,
                                              full_buffers, lod_buffers);
        m.worst[b][d].push_back(iou);
        row << "  " << iou;
      }
    }
    if (args.per_object) std::cout << row.str() << "\n";
  }
  std::cerr << "\r\x1b[K";
  return m;
}

void printTable(const Arguments& args, const Measurements& m) {
  std::cout << m.ids.size() << " objects (" << (args.category.empty() ? "all" : args.category)
            << "), " << m.full_triangles << " triangles in full; " << args.size << "x" << args.size
            << " px, 60 deg field of view, worst of " << m.views << " views each\n\n";
  std::cout << "| budget | LOD triangles | distance | worst IoU (object) | median | below "
            << args.min_iou << " |\n|---|---|---|---|---|---|\n";
  std::cout << std::fixed;
  for (std::size_t b = 0; b < args.budgets.size(); ++b) {
    for (std::size_t d = 0; d < args.distances.size(); ++d) {
      const std::vector<double>& ious = m.worst[b][d];
      const auto lowest = std::min_element(ious.begin(), ious.end());
      const long below =
          std::count_if(ious.begin(), ious.end(), [&](double iou) { return iou < args.min_iou; });
      std::cout << "| " << std::setprecision(0) << args.budgets[b] << " | " << m.lod_triangles[b]
                << " | " << std::setprecision(1) << args.distances[d] << " | "
                << std::setprecision(4) << *lowest << " (" << m.ids[lowest - ious.begin()] << ") | "
                << median(ious) << " | " << below << " |\n";
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  Arguments args;
  CLI::App app(
      "For every object of a category, simplifies its mesh to each budget and compares the "
      "silhouettes\nof the full and the simplified mesh (intersection over union, worst of eight "
      "views) with the\nobject at the origin and the camera at each distance. Prints, per budget "
      "and distance, the worst\nand the median object and how many objects fall below --min-iou.",
      "occlusion_lod_report");
  tools::addOptionFlags(app, environmentOptionTable(), args.environment,
                        {"catalog_source", "catalog_paths"});
  tools::addOptionFlags(app, argumentTable(), args);
  return tools::parseAndRun(app, argc, argv, [&args] {
    printTable(args, measure(args));
    return 0;
  });
}
