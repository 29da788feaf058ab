// A folder of mesh files, e.g. a ShapeNetCore v2 tree, read through assimp.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>

#include "assimp_mesh_loader.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/scene/object_catalog.hpp"

namespace occlusion_env {
namespace {

namespace fs = std::filesystem;

std::string lowerCase(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

bool isMeshFile(const fs::path& path) {
  static const std::set<std::string> extensions = {".obj", ".ply", ".glb", ".gltf", ".off", ".stl"};
  return extensions.count(lowerCase(path.extension().string())) > 0;
}

bool isSynsetId(const std::string& text) {
  return text.size() == 8 &&
         std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); });
}

// Object types of common ShapeNetCore synsets, in the vocabulary of the Sweet Home 3D catalogue.
std::string shapeNetType(const std::string& synset) {
  static const std::map<std::string, std::string> types = {
      {"02691156", "airplane"},  {"02747177", "trash_can"},  {"02773838", "bag"},
      {"02801938", "basket"},    {"02808440", "bathtub"},    {"02818832", "bed"},
      {"02828884", "bench"},     {"02871439", "shelf"},      {"02876657", "bottle"},
      {"02880940", "bowl"},      {"02924116", "bus"},        {"02933112", "cabinet"},
      {"02942699", "camera"},    {"02946921", "can"},        {"02954340", "cap"},
      {"02958343", "car"},       {"02992529", "phone"},      {"03001627", "chair"},
      {"03046257", "clock"},     {"03085013", "keyboard"},   {"03207941", "dishwasher"},
      {"03211117", "display"},   {"03325088", "faucet"},     {"03337140", "cabinet"},
      {"03467517", "guitar"},    {"03513137", "helmet"},     {"03593526", "jar"},
      {"03624134", "knife"},     {"03636649", "lamp"},       {"03642806", "laptop"},
      {"03691459", "speaker"},   {"03710193", "mailbox"},    {"03759954", "microphone"},
      {"03761084", "microwave"}, {"03790512", "motorcycle"}, {"03797390", "mug"},
      {"03928116", "piano"},     {"03938244", "pillow"},     {"03991062", "pot"},
      {"04004475", "printer"},   {"04256520", "sofa"},       {"04330267", "stove"},
      {"04379243", "table"},     {"04401088", "phone"},      {"04468005", "train"},
      {"04530566", "vessel"},    {"04554684", "washer"},
  };
  const auto it = types.find(synset);
  return it == types.end() ? synset : it->second;
}

class MeshFolderCatalog : public ObjectCatalog {
 public:
  explicit MeshFolderCatalog(const std::string& root) {
    std::error_code error;
    const fs::path root_path = fs::absolute(root, error);
    if (error || !fs::is_directory(root_path, error))
      throw CatalogError(root + ": mesh folder does not exist or is not a folder");
    std::vector<std::pair<ObjectInfo, Item>> entries;
    fs::recursive_directory_iterator it(root_path, fs::directory_options::skip_permission_denied,
                                        error);
    for (const fs::recursive_directory_iterator end; !error && it != end; it.increment(error)) {
      if (!it->is_regular_file(error) || !isMeshFile(it->path())) continue;
      entries.push_back(describe(root_path, it->path()));
    }
    if (error) throw CatalogError(root + ": cannot scan the mesh folder: " + error.message());
    std::sort(entries.begin(), entries.end(),
              [](const auto& a, const auto& b) { return a.first.id < b.first.id; });
    for (auto& [info, item] : entries) {
      objects_.push_back(std::move(info));
      items_.push_back(std::move(item));
    }
  }

  std::string sourceName() const override { return "folder"; }
  const std::vector<ObjectInfo>& objects() const override { return objects_; }

  Mesh loadMesh(const std::string& id) const override {
    // The id is only looked up: it never becomes a path.
    const auto it = std::lower_bound(
        objects_.begin(), objects_.end(), id,
        [](const ObjectInfo& object, const std::string& key) { return object.id < key; });
    if (it == objects_.end() || it->id != id)
      throw InvalidArgumentError("folder catalogue: unknown object id " + quoted(id));
    const Item& item = items_[it - objects_.begin()];
    Mesh mesh = detail::loadAssimpMesh(item.path, detail::readLocalFile, item.path);
    for (auto& p : mesh.positions) p = item.world_from_file * p;
    return mesh;
  }

 private:
  struct Item {
    std::string path;                 // absolute path of the mesh file
    Eigen::Matrix3f world_from_file;  // axis conversion
  };

  // ShapeNetCore v2 (<synset>/<model>/models/model_normalized.obj; y up, front -z) or any other
  // file (assumed y up, front +z like OBJ exports and glTF).
  static std::pair<ObjectInfo, Item> describe(const fs::path& root, const fs::path& file) {
    const fs::path relative = file.lexically_relative(root);
    std::vector<std::string> parts;
    for (const auto& part : relative) parts.push_back(part.string());
    ObjectInfo info;
    Item item{file.string(), detail::worldFromYUpFrontZ()};
    if (parts.size() == 4 && isSynsetId(parts[0]) && parts[2] == "models" &&
        parts[3] == "model_normalized.obj") {
      info.id = parts[0] + "/" + parts[1];
      info.name = parts[1];
      info.source_category = parts[0];
      info.category = shapeNetType(parts[0]);
      info.license = "ShapeNet terms of use";
      item.world_from_file = detail::worldFromYUpFrontMinusZ();
    } else {
      info.id = relative.generic_string();
      info.name = file.stem().string();
      info.source_category = file.parent_path().filename().string();
      info.category = lowerCase(info.source_category);
    }
    return {std::move(info), std::move(item)};
  }

  std::vector<ObjectInfo> objects_;  // sorted by id
  std::vector<Item> items_;          // parallel to objects_
};

}  // namespace

std::unique_ptr<ObjectCatalog> makeMeshFolderCatalog(const std::string& root) {
  return std::make_unique<MeshFolderCatalog>(root);
}

}  // namespace occlusion_env
