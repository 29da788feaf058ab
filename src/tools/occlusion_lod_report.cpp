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
#include "occlusion_env/geometry/camera.hpp"
#include "occlusion_env/render/lod_quality.hpp"
#include "occlusion_env/render/osmesa_renderer.hpp"
#include "occlusion_env/scene/object_library.hpp"
#include "occlusion_env/tools/arguments.hpp"

namespace {

constexpr const char* kUsage = R"(Usage: occlusion_lod_report [options]
For every object of a category, simplifies its mesh to each budget and compares the silhouettes
of the full and the simplified mesh (intersection over union, worst of eight views) with the
object at the origin and the camera at each distance. Prints, per budget and distance, the worst
and the median object and how many objects fall below --min-iou.

Options:
  --source S          embedded | sweethome3d | folder (default sweethome3d)
  --path P            a .sh3f file or folder (sweethome3d), the root (folder); repeatable
  --category C        objects of this category ("" = all; default chair)
  --budgets LIST      triangle budgets, comma-separated (default 3000,4000,5000,6000,8000)
  --distances LIST    camera distances in object diagonals (default 1.0,1.6,2.5; the LOD test
                      uses 1.6, where the diagonal spans about half of the image)
  --size N            image width and height [px] (default 256)
  --min-iou X         the threshold counted against (default 0.98)
  --per-object        also print each object's worst IoU
  --help              this text
)";

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The silhouettes' worst IoU of each object's level-of-detail meshes against its full mesh.
struct LodMeasurements {
  std::vector<std::vector<std::vector<double>>> worst;  // [budget][distance][object]
  std::vector<std::size_t> lod_triangles;               // per budget, all objects together
  std::size_t full_triangles = 0;
};

// Measures every object of `ids` at every budget and distance; with `per_object` prints each
// object's row as it is measured.
LodMeasurements measureLods(occlusion_env::ObjectLibrary& library,
                            occlusion_env::Renderer& renderer, const std::vector<std::string>& ids,
                            const std::vector<double>& budgets,
                            const std::vector<double>& distances, bool per_object) {
  using namespace occlusion_env;
  const std::vector<SphericalPose> views = silhouetteCheckViews();
  RenderBuffers full_buffers, lod_buffers;
  LodMeasurements m;
  m.worst.assign(budgets.size(), std::vector<std::vector<double>>(distances.size()));
  m.lod_triangles.assign(budgets.size(), 0);
  for (std::size_t o = 0; o < ids.size(); ++o) {
    std::cerr << "\r" << (o + 1) << "/" << ids.size() << " " << ids[o] << "\x1b[K" << std::flush;
    const auto model = library.get(ids[o]);
    m.full_triangles += model->full.triangleCount();
    std::ostringstream row;
    row << std::fixed << std::setprecision(4) << std::left << std::setw(44) << ids[o] << std::right
        << std::setw(8) << model->full.triangleCount();
    for (std::size_t b = 0; b < budgets.size(); ++b) {
      const Mesh lod = simplifyMesh(model->full, static_cast<std::size_t>(budgets[b]));
      m.lod_triangles[b] += lod.triangleCount();
      for (std::size_t d = 0; d < distances.size(); ++d) {
        const SphericalCamera camera(distances[d], 1.3);
        const double iou = worstSilhouetteIou(renderer, model->full, lod, camera, views,
                                              full_buffers, lod_buffers);
        m.worst[b][d].push_back(iou);
        row << "  " << iou;
      }
    }
    if (per_object) std::cout << row.str() << "\n";
  }
  std::cerr << "\r\x1b[K";
  return m;
}

// Per budget and distance: the worst object, the median and how many fall below `min_iou`.
void printLodTable(const LodMeasurements& m, const std::vector<std::string>& ids,
                   const std::vector<double>& budgets, const std::vector<double>& distances,
                   double min_iou) {
  std::cout << "| budget | LOD triangles | distance | worst IoU (object) | median | below "
            << min_iou << " |\n|---|---|---|---|---|---|\n";
  std::cout << std::fixed;
  for (std::size_t b = 0; b < budgets.size(); ++b) {
    for (std::size_t d = 0; d < distances.size(); ++d) {
      const std::vector<double>& ious = m.worst[b][d];
      const auto lowest = std::min_element(ious.begin(), ious.end());
      const long below =
          std::count_if(ious.begin(), ious.end(), [&](double iou) { return iou < min_iou; });
      std::cout << "| " << std::setprecision(0) << budgets[b] << " | " << m.lod_triangles[b]
                << " | " << std::setprecision(1) << distances[d] << " | " << std::setprecision(4)
                << *lowest << " (" << ids[lowest - ious.begin()] << ") | " << median(ious) << " | "
                << below << " |\n";
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  CatalogOptions catalog_options;
  catalog_options.source = "sweethome3d";
  std::string category = "chair";
  std::vector<double> budgets{3000, 4000, 5000, 6000, 8000}, distances{1.0, 1.6, 2.5};
  int size = 256;
  double min_iou = 0.98;
  bool per_object = false;
  try {
    tools::ArgumentReader args(argc, argv);
    while (args.next()) {
      const std::string& flag = args.flag();
      if (flag == "--help" || flag == "-h") {
        std::cout << kUsage;
        return 0;
      } else if (flag == "--source") {
        catalog_options.source = args.text();
      } else if (flag == "--path") {
        catalog_options.paths.push_back(args.text());
      } else if (flag == "--category") {
        category = args.text();
      } else if (flag == "--budgets") {
        budgets = args.numbers(1.0, 1e9);
      } else if (flag == "--distances") {
        distances = args.numbers(0.6, 1e3);  // outside the object's bounding sphere
      } else if (flag == "--size") {
        size = static_cast<int>(args.integer(1, 1 << 16));
      } else if (flag == "--min-iou") {
        min_iou = args.number(0.0, 1.0);
      } else if (flag == "--per-object") {
        per_object = true;
      } else {
        args.unknown();
      }
    }
  } catch (const tools::ArgumentError& error) {
    std::cerr << "occlusion_lod_report: " << error.what() << "\n" << kUsage;
    return 2;
  }

  try {
    std::shared_ptr<const ObjectCatalog> catalog = makeCatalog(catalog_options);
    std::vector<std::string> ids;
    if (category.empty()) {
      for (const ObjectInfo& info : catalog->objects()) ids.push_back(info.id);
    } else {
      ids = catalog->idsInCategory(category);
    }
    if (ids.empty()) throw CatalogError("no object in category '" + category + "'");
    ObjectLibrary library(catalog, 0);  // full meshes; the budgets are applied here
    auto renderer = makeOsMesaRenderer(CameraIntrinsics::fromFieldOfView(size, size, M_PI / 3.0));
    const LodMeasurements m = measureLods(library, *renderer, ids, budgets, distances, per_object);
    std::cout << ids.size() << " objects (" << (category.empty() ? "all" : category) << "), "
              << m.full_triangles << " triangles in full; " << size << "x" << size
              << " px, 60 deg field of view, worst of " << silhouetteCheckViews().size()
              << " views each\n\n";
    printLodTable(m, ids, budgets, distances, min_iou);
  } catch (const std::exception& error) {
    std::cerr << "\nocclusion_lod_report: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
