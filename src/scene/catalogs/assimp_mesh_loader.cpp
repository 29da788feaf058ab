#include "assimp_mesh_loader.hpp"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace detail {
namespace {

// Read-only stream over bytes it owns.
class StringStream : public Assimp::IOStream {
 public:
  explicit StringStream(std::string data) : data_(std::move(data)) {}
  size_t Read(void* buffer, size_t size, size_t count) override {
    if (size == 0) return 0;
    const size_t items = std::min(count, (data_.size() - position_) / size);
    std::memcpy(buffer, data_.data() + position_, items * size);
    position_ += items * size;
    return items;
  }
  size_t Write(const void*, size_t, size_t) override { return 0; }
  aiReturn Seek(size_t offset, aiOrigin origin) override {
    const size_t base = origin == aiOrigin_SET   ? 0
                        : origin == aiOrigin_CUR ? position_
                                                 : data_.size();
    if (base + offset > data_.size()) return aiReturn_FAILURE;
    position_ = base + offset;
    return aiReturn_SUCCESS;
  }
  size_t Tell() const override { return position_; }
  size_t FileSize() const override { return data_.size(); }
  void Flush() override {}

 private:
  std::string data_;
  size_t position_ = 0;
};

// Serves assimp's file requests (the model, its .mtl, glTF buffers) through a FileReader.
class ReaderIOSystem : public Assimp::IOSystem {
 public:
  explicit ReaderIOSystem(const FileReader& read) : read_(read) {}
  bool Exists(const char* file) const override { return fetch(file) != nullptr; }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (mode != nullptr && std::strchr(mode, 'w') != nullptr) return nullptr;  // read-only
    const std::string* data = fetch(file);
    return data == nullptr ? nullptr : new StringStream(*data);
  }
  void Close(Assimp::IOStream* stream) override { delete stream; }

 private:
  // Reads each file once per load; nullptr when absent.
  const std::string* fetch(const char* file) const {
    const std::string path = normalizePath(file);
    auto it = files_.find(path);
    if (it == files_.end()) it = files_.emplace(path, read_(path)).first;
    return it->second ? &*it->second : nullptr;
  }

  const FileReader& read_;
  mutable std::map<std::string, std::optional<std::string>> files_;
};

float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// 8-bit sRGB -> linear, by table.
const std::array<float, 256>& srgbTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = srgbToLinear(i / 255.0f);
    return t;
  }();
  return table;
}

// Bilinear sample of an 8-bit BGR image at (u, v), wrapping; v = 0 is the image's bottom row.
Eigen::Vector3f sampleTexture(const cv::Mat& bgr, float u, float v) {
  const auto& to_linear = srgbTable();
  const float x = (u - std::floor(u)) * bgr.cols - 0.5f;
  const float y = (1.0f - (v - std::floor(v))) * bgr.rows - 0.5f;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float fx = x - x0, fy = y - y0;
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  for (int dy = 0; dy <= 1; ++dy) {
    for (int dx = 0; dx <= 1; ++dx) {
      const int col = ((x0 + dx) % bgr.cols + bgr.cols) % bgr.cols;
      const int row = ((y0 + dy) % bgr.rows + bgr.rows) % bgr.rows;
      const cv::Vec3b& texel = bgr.at<cv::Vec3b>(row, col);
      const float weight = (dx ? fx : 1.0f - fx) * (dy ? fy : 1.0f - fy);
      sum +=
          weight * Eigen::Vector3f(to_linear[texel[2]], to_linear[texel[1]], to_linear[texel[0]]);
    }
  }
  return sum;
}

std::string folderOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

// Decodes the textures the materials name, each once per load; empty Mat when unavailable.
class TextureCache {
 public:
  TextureCache(const aiScene& scene, const std::string& model_path, const FileReader& read)
      : scene_(scene), folder_(folderOf(model_path)), read_(read) {}

  const cv::Mat& get(const std::string& name) {
    auto it = textures_.find(name);
    if (it == textures_.end()) it = textures_.emplace(name, decode(name)).first;
    return it->second;
  }

 private:
  cv::Mat decode(const std::string& name) const {
    cv::Mat image;
    try {
      if (const aiTexture* embedded = scene_.GetEmbeddedTexture(name.c_str())) {
        if (embedded->mHeight == 0) {  // compressed file bytes (png, jpg)
          const cv::Mat bytes(1, static_cast<int>(embedded->mWidth), CV_8U, embedded->pcData);
          image = cv::imdecode(bytes, cv::IMREAD_COLOR);
        } else {  // raw BGRA texels
          const cv::Mat bgra(static_cast<int>(embedded->mHeight),
                             static_cast<int>(embedded->mWidth), CV_8UC4, embedded->pcData);
          cv::cvtColor(bgra, image, cv::COLOR_BGRA2BGR);
        }
        return image;
      }
      // Relative to the model's folder; else the bare file name there (absolute or foreign paths).
      const std::string relative = normalizePath(folder_ + name);
      const std::string normalized = normalizePath(name);
      const std::string base = normalized.substr(normalized.find_last_of('/') + 1);
      for (const std::string& candidate : {relative, normalizePath(folder_ + base)}) {
        if (std::optional<std::string> bytes = read_(candidate)) {
          const cv::Mat raw(1, static_cast<int>(bytes->size()), CV_8U, bytes->data());
          image = cv::imdecode(raw, cv::IMREAD_COLOR);
          if (!image.empty()) break;
        }
      }
    } catch (const cv::Exception&) {
      image.release();  // an undecodable texture leaves the material colour
    }
    return image;
  }

  const aiScene& scene_;
  std::string folder_;
  const FileReader& read_;
  std::map<std::string, cv::Mat> textures_;
};

Eigen::Vector3f diffuseColour(const aiMaterial& material) {
  aiColor4D colour(0.8f, 0.8f, 0.8f, 1.0f);
  if (aiGetMaterialColor(&material, AI_MATKEY_COLOR_DIFFUSE, &colour) != AI_SUCCESS)
    aiGetMaterialColor(&material, AI_MATKEY_BASE_COLOR, &colour);
  return Eigen::Vector3f(colour.r, colour.g, colour.b).cwiseMax(0.0f).cwiseMin(1.0f);
}

std::optional<std::string> diffuseTextureName(const aiMaterial& material) {
  aiString name;
  for (aiTextureType type : {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR})
    if (material.GetTextureCount(type) > 0 && material.GetTexture(type, 0, &name) == AI_SUCCESS &&
        name.length > 0)
      return std::string(name.C_Str());
  return std::nullopt;
}

// Appends the triangles of `source` with their colours.
void appendAssimpMesh(Mesh& mesh, const aiMesh& source, const aiScene& scene,
                      TextureCache& textures) {
  const aiMaterial* material = source.mMaterialIndex < scene.mNumMaterials
                                   ? scene.mMaterials[source.mMaterialIndex]
                                   : nullptr;
  const Eigen::Vector3f diffuse =
      material != nullptr ? diffuseColour(*material) : Eigen::Vector3f(0.8f, 0.8f, 0.8f);
  const cv::Mat* texture = nullptr;
  if (material != nullptr && source.HasTextureCoords(0)) {
    if (const auto name = diffuseTextureName(*material)) {
      const cv::Mat& image = textures.get(*name);
      if (!image.empty()) texture = &image;
    }
  }
  const auto& to_linear = srgbTable();
  const auto offset = static_cast<std::uint32_t>(mesh.positions.size());
  for (unsigned v = 0; v < source.mNumVertices; ++v) {
    const aiVector3D& p = source.mVertices[v];
    mesh.positions.emplace_back(p.x, p.y, p.z);
    Eigen::Vector3f colour = diffuse;
    if (source.HasVertexColors(0)) {  // the file's own colours (8-bit sRGB scaled to [0, 1])
      const aiColor4D& c = source.mColors[0][v];
      auto channel = [&](float x) { return to_linear[std::clamp(int(x * 255.0f + 0.5f), 0, 255)]; };
      colour = Eigen::Vector3f(channel(c.r), channel(c.g), channel(c.b));
    } else if (texture != nullptr) {
      const aiVector3D& uv = source.mTextureCoords[0][v];
      colour = sampleTexture(*texture, uv.x, uv.y).cwiseProduct(diffuse);
    }
    mesh.colors.push_back(colour);
  }
  for (unsigned f = 0; f < source.mNumFaces; ++f) {
    const aiFace& face = source.mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines
    for (int k = 0; k < 3; ++k) mesh.indices.push_back(offset + face.mIndices[k]);
  }
}

}  // namespace

std::string normalizePath(const std::string& path) {
  std::vector<std::string> parts;
  std::string part;
  std::string unified = path;
  std::replace(unified.begin(), unified.end(), '\\', '/');
  std::size_t start = 0;
  while (start <= unified.size()) {
    std::size_t end = unified.find('/', start);
    if (end == std::string::npos) end = unified.size();
    part = unified.substr(start, end - start);
    if (part == "..") {
      if (!parts.empty()) parts.pop_back();
    } else if (!part.empty() && part != ".") {
      parts.push_back(part);
    }
    start = end + 1;
  }
  std::string normalized = !unified.empty() && unified[0] == '/' ? "/" : "";
  for (std::size_t i = 0; i < parts.size(); ++i) normalized += (i ? "/" : "") + parts[i];
  return normalized;
}

Mesh loadAssimpMesh(const std::string& path, const FileReader& read, const std::string& what) {
  Assimp::Importer importer;
  importer.SetIOHandler(new ReaderIOSystem(read));  // the importer owns it
  const aiScene* scene = importer.ReadFile(
      normalizePath(path),
      aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices);
  if (scene == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0)
    throw CatalogError(what + ": cannot read the mesh: " + importer.GetErrorString());
  Mesh mesh;
  TextureCache textures(*scene, normalizePath(path), read);
  for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    appendAssimpMesh(mesh, *scene->mMeshes[m], *scene, textures);
  validateMesh(mesh, what);
  return mesh;
}

Eigen::Matrix3f worldFromYUpFrontZ() {
  Eigen::Matrix3f rotation;
  rotation << 0, 0, 1,  // x = z_src (front)
      1, 0, 0,          // y = x_src
      0, 1, 0;          // z = y_src (up)
  return rotation;
}

Eigen::Matrix3f worldFromYUpFrontMinusZ() {
  Eigen::Matrix3f rotation;
  rotation << 0, 0, -1,  // x = -z_src (front)
      -1, 0, 0,          // y = -x_src
      0, 1, 0;           // z = y_src (up)
  return rotation;
}

std::optional<std::string> readLocalFile(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return std::nullopt;
  std::ifstream file(path, std::ios::binary);
  if (!file) return std::nullopt;
  std::ostringstream bytes;
  bytes << file.rdbuf();
  if (!file && !file.eof()) return std::nullopt;
  return bytes.str();
}

}  // namespace detail
}  // namespace occlusion_env
