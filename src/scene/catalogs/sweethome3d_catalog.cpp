// Sweet Home 3D furniture catalogues (.sh3f: a zip holding PluginFurnitureCatalog.properties and
// the OBJ models with their materials and textures).
#include <zip.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <locale>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>

#include "assimp_mesh_loader.hpp"
#include "java_properties.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/scene/object_catalog.hpp"

namespace occlusion_env {
namespace {

namespace fs = std::filesystem;

constexpr char kDebianFurnitureDir[] = "/usr/share/sweethome3d/furniture";
constexpr char kIndexEntry[] = "PluginFurnitureCatalog.properties";

std::string lowerCase(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

bool hasSh3fExtension(const fs::path& path) {
  return lowerCase(path.extension().string()) == ".sh3f";
}

// ---------------------------------------------------------------------------------------------
// Object type from the item's English name.
// The type is the rightmost word of the name's head (before ",", " with ", " and ", ...) that is
// a known keyword: "Desk lamp" -> lamp, "Bedside table" -> table, "Table fan" -> fan. Decisions:
// chair includes armchairs, deck/high/folding chairs (not wheelchairs, not stools); stool and bench
// are their own types; table includes desks, workbenches and game tables (pool, table tennis);
// shelf includes bookcases; cabinet includes cupboards, wardrobes, dressers and vanities; lamp
// includes every light and lantern; plant includes trees, hedges and flowers. Words such as
// "stand" or "cake" stop the search ("TV stand", "Cup cake" -> other).
// ---------------------------------------------------------------------------------------------
const std::unordered_map<std::string, std::string>& typeKeywords() {
  static const std::unordered_map<std::string, std::string> keywords = [] {
    const std::vector<std::pair<std::string, std::vector<std::string>>> groups = {
        {"chair", {"chair", "armchair"}},
        {"stool", {"stool"}},
        {"bench", {"bench"}},
        {"sofa", {"sofa", "couch", "futon"}},
        {"table", {"table", "desk", "workbench"}},
        {"bed", {"bed", "crib", "mattress"}},
        {"cabinet", {"cabinet", "cupboard", "wardrobe", "dresser", "locker", "vanity"}},
        {"shelf", {"shelf", "shelves", "bookcase", "bookshelf"}},
        {"lamp", {"lamp", "light", "chandelier", "lantern", "lamppost", "spotlight"}},
        {"plant", {"plant",  "tree",   "bush",  "hedge",  "cactus",        "bamboo", "ficus",
                   "yucca",  "orchid", "tulip", "flower", "bonsai",        "pine",   "cypress",
                   "poplar", "acacia", "maple", "beech",  "spathiphyllum", "lily",   "blossom"}},
        {"mug", {"mug"}},
        {"cup", {"cup"}},
        {"glass", {"glass"}},
        {"bottle", {"bottle", "flacon"}},
        {"bowl", {"bowl"}},
        {"vase", {"vase"}},
        {"plate", {"plate"}},
        {"box", {"box", "crate"}},
        {"book", {"book"}},
        {"clock", {"clock"}},
        {"tv", {"tv", "television"}},
        {"computer", {"computer", "imac", "ibook"}},
        {"laptop", {"laptop"}},
        {"phone", {"phone", "iphone"}},
        {"speaker", {"speaker"}},
        {"fan", {"fan"}},
        {"piano", {"piano"}},
        {"radiator", {"radiator"}},
        {"fireplace", {"fireplace"}},
        {"fridge", {"fridge", "refrigerator", "freezer"}},
        {"oven", {"oven"}},
        {"microwave", {"microwave"}},
        {"stove", {"stove", "cooker", "cooktop"}},
        {"sink", {"sink", "washbasin", "basin", "lavatory"}},
        {"toilet", {"toilet"}},
        {"bathtub", {"bath", "bathtub", "jacuzzi"}},
        {"door", {"door"}},
        {"window", {"window"}},
        {"person", {"male", "female", "boy", "girl", "man", "woman", "mannequin"}},
        {"animal", {"dog", "bulldog", "cat", "deer", "rabbit", "horse"}},
        {"car",
         {"car", "sedan", "suv", "van", "chevrolet", "ford", "peugeot", "renault", "beetle",
          "leon"}},
        {"bus", {"bus"}},
        {"truck", {"truck"}},
        {"motorcycle", {"motorbike", "motorcycle", "yamaha"}},
        {"bicycle", {"bicycle", "bike"}},
        {"trash_can", {"dustbin", "trashcan", "bin", "can"}},
        {"washer", {"washing", "dryer"}},
        {"keyboard", {"keyboard"}},
        {"camera", {"camera", "cctv"}},
        {"guitar", {"guitar"}},
        {"knife", {"knife"}},
        {"helmet", {"helmet"}},
        {"bag", {"bag", "backpack", "handbag", "suitcase", "briefcase"}},
        {"printer", {"printer"}},
        {"mailbox", {"mailbox"}},
        {"other",
         {"stand", "bat", "cake", "house", "hut", "holder", "dispenser", "brush", "remote", "net",
          "goal", "game"}},
    };
    std::unordered_map<std::string, std::string> map;
    for (const auto& [type, words] : groups)
      for (const auto& word : words) map.emplace(word, type);
    return map;
  }();
  return keywords;
}

std::string objectTypeFromName(const std::string& name) {
  std::string head = lowerCase(name);
  // Whole names where the rightmost keyword misleads.
  static const std::map<std::string, std::string> exceptions = {{"rocking horse", "other"},
                                                                {"clothes horse", "other"}};
  if (auto it = exceptions.find(head); it != exceptions.end()) return it->second;
  for (const char* qualifier : {",", " with ", " and ", " on ", " under ", " of ", " for "})
    if (const auto pos = head.find(qualifier); pos != std::string::npos) head.resize(pos);

  std::vector<std::string> words;
  std::string word;
  for (char c : head + ' ') {
    if (std::isalnum(static_cast<unsigned char>(c))) {
      word += c;
    } else if (!word.empty()) {
      words.push_back(word);
      word.clear();
    }
  }
  const auto& keywords = typeKeywords();
  for (auto it = words.rbegin(); it != words.rend(); ++it) {
    if (auto found = keywords.find(*it); found != keywords.end()) return found->second;
    if (it->size() > 1 && it->back() == 's')  // simple plural
      if (auto found = keywords.find(it->substr(0, it->size() - 1)); found != keywords.end())
        return found->second;
  }
  return "other";
}

// ---------------------------------------------------------------------------------------------
// Zip access (libzip). Each load opens its own handle, so loads may run in parallel.
// ---------------------------------------------------------------------------------------------
struct ZipCloser {
  void operator()(zip_t* archive) const { zip_discard(archive); }  // read-only: nothing to write
};
using ZipHandle = std::unique_ptr<zip_t, ZipCloser>;

ZipHandle openZip(const std::string& path) {
  int error_code = 0;
  zip_t* archive = zip_open(path.c_str(), ZIP_RDONLY, &error_code);
  if (archive == nullptr) {
    zip_error_t error;
    zip_error_init_with_code(&error, error_code);
    const std::string message = zip_error_strerror(&error);
    zip_error_fini(&error);
    throw CatalogError(path + ": cannot open as a Sweet Home 3D catalogue (zip): " + message);
  }
  return ZipHandle(archive);
}

// Bytes of the entry `name` (exact, else case-insensitive match); nullopt when absent or
// unreadable.
std::optional<std::string> readZipEntry(zip_t* archive, const std::string& name) {
  zip_int64_t index = zip_name_locate(archive, name.c_str(), 0);
  if (index < 0) index = zip_name_locate(archive, name.c_str(), ZIP_FL_NOCASE);
  zip_stat_t stat;
  if (index < 0 || zip_stat_index(archive, index, 0, &stat) != 0 ||
      (stat.valid & ZIP_STAT_SIZE) == 0)
    return std::nullopt;
  zip_file_t* file = zip_fopen_index(archive, index, 0);
  if (file == nullptr) return std::nullopt;
  std::string bytes(stat.size, '\0');
  const zip_int64_t read = zip_fread(file, bytes.data(), bytes.size());
  zip_fclose(file);
  if (read < 0 || static_cast<zip_uint64_t>(read) != stat.size) return std::nullopt;
  return bytes;
}

std::string zipEntryName(const std::string& path) {
  std::string name = detail::normalizePath(path);
  if (!name.empty() && name[0] == '/') name.erase(0, 1);
  return name;
}

float parseFloat(const std::string& text, float fallback) {
  float value = fallback;
  const char* begin = text.data();
  while (begin != text.data() + text.size() && std::isspace(static_cast<unsigned char>(*begin)))
    ++begin;
  const auto result = std::from_chars(begin, text.data() + text.size(), value);
  return result.ec == std::errc() && std::isfinite(value) ? value : fallback;
}

// "m00 m01 m02 m10 ... m22" (row-major, Sweet Home 3D's modelRotation); identity when malformed.
Eigen::Matrix3f parseRotation(const std::string& text) {
  std::vector<float> values;
  std::istringstream stream(text);
  stream.imbue(std::locale::classic());
  for (float value; stream >> value;) values.push_back(value);
  Eigen::Matrix3f rotation = Eigen::Matrix3f::Identity();
  if (values.size() == 9)
    for (int i = 0; i < 9; ++i) rotation(i / 3, i % 3) = values[i];
  return rotation;
}

// ---------------------------------------------------------------------------------------------
// The catalogue.
// ---------------------------------------------------------------------------------------------
struct Item {
  std::string archive;             // .sh3f path
  std::string model;               // zip entry of the OBJ
  Eigen::Matrix3f model_rotation;  // applied to the OBJ's coordinates first (Sweet Home 3D axes)
  Eigen::Vector3f size_cm;         // width (x), height (y), depth (z) in Sweet Home 3D axes
};

class SweetHome3DCatalog : public ObjectCatalog {
 public:
  explicit SweetHome3DCatalog(const std::vector<std::string>& archives) {
    std::vector<std::pair<ObjectInfo, Item>> entries;
    std::set<std::string> ids;
    for (const auto& archive : archives) readIndex(archive, ids, entries);
    std::sort(entries.begin(), entries.end(),
              [](const auto& a, const auto& b) { return a.first.id < b.first.id; });
    for (auto& [info, item] : entries) {
      objects_.push_back(std::move(info));
      items_.push_back(std::move(item));
    }
  }

  std::string sourceName() const override { return "sweethome3d"; }
  const std::vector<ObjectInfo>& objects() const override { return objects_; }

  Mesh loadMesh(const std::string& id) const override {
    const auto it =
        std::lower_bound(objects_.begin(), objects_.end(), id,
                         [](const ObjectInfo& o, const std::string& k) { return o.id < k; });
    if (it == objects_.end() || it->id != id)
      throw InvalidArgumentError("sweethome3d catalogue: unknown object id " + quoted(id));
    const Item& item = items_[it - objects_.begin()];
    const std::string what = item.archive + ": " + id + " (" + item.model + ")";

    ZipHandle archive = openZip(item.archive);
    const detail::FileReader read = [&](const std::string& path) {
      return readZipEntry(archive.get(), zipEntryName(path));
    };
    if (!read(item.model)) throw CatalogError(what + ": model missing from the archive");
    Mesh mesh = detail::loadAssimpMesh(item.model, read, what);

    // As Sweet Home 3D shows it: rotated by modelRotation, then stretched to the catalogue's
    // width x height x depth (cm -> m). Axes without a size take the mean scale of the others.
    for (auto& p : mesh.positions) p = item.model_rotation * p;
    const Eigen::Vector3f extent = boundingBox(mesh).sizes();
    Eigen::Vector3f scale = Eigen::Vector3f::Zero();
    float scale_sum = 0.0f;
    int scale_count = 0;
    for (int axis = 0; axis < 3; ++axis) {
      if (item.size_cm[axis] > 0.0f && extent[axis] > 1e-9f) {
        scale[axis] = 0.01f * item.size_cm[axis] / extent[axis];
        scale_sum += scale[axis];
        ++scale_count;
      }
    }
    const float mean_scale = scale_count > 0 ? scale_sum / scale_count : 0.01f;  // else cm
    for (int axis = 0; axis < 3; ++axis)
      if (scale[axis] == 0.0f) scale[axis] = mean_scale;
    const Eigen::Matrix3f world_from_model = detail::worldFromYUpFrontZ() * scale.asDiagonal();
    for (auto& p : mesh.positions) p = world_from_model * p;
    validateMesh(mesh, what);
    return mesh;
  }

 private:
  // Appends the items of one .sh3f; ids already taken get the archive's stem as prefix.
  static void readIndex(const std::string& archive_path, std::set<std::string>& ids,
                        std::vector<std::pair<ObjectInfo, Item>>& entries) {
    ZipHandle archive = openZip(archive_path);
    const std::optional<std::string> index = readZipEntry(archive.get(), kIndexEntry);
    if (!index)
      throw CatalogError(archive_path + ": no " + std::string(kIndexEntry) +
                         " (not a Sweet Home 3D furniture catalogue)");
    std::map<std::string, std::string> properties;
    try {
      properties = detail::parseJavaProperties(*index);
    } catch (const CatalogError& error) {
      throw CatalogError(archive_path + ": " + kIndexEntry + ": " + error.what());
    }
    auto value = [&](const std::string& key) {
      const auto it = properties.find(key);
      return it == properties.end() ? std::string() : it->second;
    };

    // Item numbers, from the "model#N" keys.
    std::vector<long> numbers;
    for (const auto& [key, model] : properties) {
      if (key.rfind("model#", 0) != 0) continue;
      const std::string digits = key.substr(6);
      long number = 0;
      const auto result = std::from_chars(digits.data(), digits.data() + digits.size(), number);
      if (result.ec == std::errc() && result.ptr == digits.data() + digits.size())
        numbers.push_back(number);
    }
    std::sort(numbers.begin(), numbers.end());

    const std::string stem = fs::path(archive_path).stem().string();
    const std::string license = value("license");
    for (long number : numbers) {
      const std::string n = "#" + std::to_string(number);
      ObjectInfo info;
      info.id = value("id" + n);
      if (info.id.empty()) info.id = stem + n;
      if (ids.count(info.id)) info.id = stem + "/" + info.id;
      if (ids.count(info.id)) info.id += n;
      ids.insert(info.id);
      info.name = value("name" + n);
      info.source_category = value("category" + n);
      info.category = objectTypeFromName(info.name);
      info.creator = value("creator" + n);
      info.license = license;
      const float width = parseFloat(value("width" + n), 0.0f);
      const float depth = parseFloat(value("depth" + n), 0.0f);
      const float height = parseFloat(value("height" + n), 0.0f);
      info.dimensions_m = 0.01f * Eigen::Vector3f(width, depth, height);
      Item item{archive_path, zipEntryName(value("model" + n)),
                parseRotation(value("modelRotation" + n)), Eigen::Vector3f(width, height, depth)};
      entries.emplace_back(std::move(info), std::move(item));
    }
  }

  std::vector<ObjectInfo> objects_;  // sorted by id
  std::vector<Item> items_;          // parallel to objects_
};

}  // namespace

std::vector<std::string> defaultSweetHome3DCatalogPaths() {
  std::vector<std::string> paths;
  std::error_code error;
  for (fs::directory_iterator it(kDebianFurnitureDir, error), end; !error && it != end;
       it.increment(error))
    if (it->is_regular_file(error) && hasSh3fExtension(it->path()))
      paths.push_back(it->path().string());
  std::sort(paths.begin(), paths.end());
  return paths;
}

std::unique_ptr<ObjectCatalog> makeSweetHome3DCatalog(const std::vector<std::string>& paths) {
  std::vector<std::string> archives;
  for (const auto& path : paths) {
    std::error_code error;
    if (fs::is_directory(path, error)) {
      std::vector<std::string> found;
      for (fs::directory_iterator it(path, error), end; !error && it != end; it.increment(error))
        if (it->is_regular_file(error) && hasSh3fExtension(it->path()))
          found.push_back(it->path().string());
      if (found.empty()) throw CatalogError(path + ": folder holds no .sh3f catalogue");
      std::sort(found.begin(), found.end());
      archives.insert(archives.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(path, error)) {
      archives.push_back(path);
    } else {
      throw CatalogError(path + ": no such Sweet Home 3D catalogue (.sh3f file or folder)");
    }
  }
  if (archives.empty()) throw CatalogError("sweethome3d catalogue: no .sh3f files given");
  return std::make_unique<SweetHome3DCatalog>(archives);
}

}  // namespace occlusion_env
