// Object catalogues (properties parser, Sweet Home 3D, mesh folder) and the object library.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "../../src/scene/catalogs/assimp_mesh_loader.hpp"
#include "../../src/scene/catalogs/java_properties.hpp"
#include "common/temporary_dir.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/scene/object_catalog.hpp"
#include "occlusion_env/scene/object_library.hpp"

namespace occlusion_env {
namespace {

namespace fs = std::filesystem;

constexpr char kOakChairId[] = "Blend Swap CC-0#oakChair";  // model /blendswap-cc-0/oakChair/...

// Expects `call` to throw E whose message contains `part`.
template <typename E, typename F>
void expectThrowMentioning(F&& call, const std::string& part) {
  try {
    call();
    ADD_FAILURE() << "no exception; expected one mentioning " << part;
  } catch (const E& error) {
    EXPECT_NE(std::string(error.what()).find(part), std::string::npos) << error.what();
  }
}

// A fresh folder under the system's temp dir, removed afterwards, and files written into it.
class TempDirTest : public TemporaryDirTest {
 protected:
  std::string write(const std::string& relative, const std::string& content) const {
    const fs::path path = dir_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << content;
    return path.string();
  }
};

// ---------------------------------------------------------------------------------------------
// Java properties
// ---------------------------------------------------------------------------------------------
TEST(JavaPropertiesTest, ParsesSeparatorsCommentsContinuationsAndEscapes) {
  const std::string text =
      "# comment = ignored\r\n"
      "  ! another comment\n"
      "\n"
      "plain=value\n"
      "colon:value2\n"
      "spaced   =   padded value  \n"
      "blank separated\n"
      "   indented=yes\n"
      "continued=first \\\n"
      "     second \\\n"
      "\tthird\n"
      "escapes=tab\\there\\nline\\\\back \\u00e9\\u20AC\n"
      "key\\=with\\:separators=v\n"
      "trailing=two backslashes\\\\\n"
      "not=continued\n"
      "emoji=\\uD83D\\uDE00\n"
      "latin1=\xA9 2008\n"
      "empty=\n"
      "plain=replaced";
  const auto p = detail::parseJavaProperties(text);
  EXPECT_EQ(p.count("# comment "), 0u);
  EXPECT_EQ(p.at("plain"), "replaced");
  EXPECT_EQ(p.at("colon"), "value2");
  EXPECT_EQ(p.at("spaced"), "padded value  ");
  EXPECT_EQ(p.at("blank"), "separated");
  EXPECT_EQ(p.at("indented"), "yes");
  EXPECT_EQ(p.at("continued"), "first second third");
  EXPECT_EQ(p.at("escapes"), "tab\there\nline\\back \xC3\xA9\xE2\x82\xAC");
  EXPECT_EQ(p.at("key=with:separators"), "v");
  EXPECT_EQ(p.at("trailing"), "two backslashes\\");
  EXPECT_EQ(p.at("not"), "continued");
  EXPECT_EQ(p.at("emoji"), "\xF0\x9F\x98\x80");
  EXPECT_EQ(p.at("latin1"), "\xC2\xA9 2008");  // not UTF-8: read as ISO-8859-1
  EXPECT_EQ(p.at("empty"), "");
  EXPECT_EQ(p.size(), 13u);
}

TEST(JavaPropertiesTest, KeepsUtf8AndRejectsMalformedUnicodeEscape) {
  EXPECT_EQ(detail::parseJavaProperties("name=Frame H\xC3\xB4i An").at("name"),
            "Frame H\xC3\xB4i An");
  expectThrowMentioning<CatalogError>([] { detail::parseJavaProperties("a=1\nb=\\u12G4"); },
                                      "line 2");
}

// Found by test/fuzz/java_properties_fuzzer: the result must be valid UTF-8 whatever the input.
TEST(JavaPropertiesTest, UnpairedSurrogatesAndInvalidUtf8GiveValidUtf8) {
  // A surrogate pair makes one code point (U+1F600); unpaired halves become U+FFFD.
  EXPECT_EQ(detail::parseJavaProperties("a=\\uD83D\\uDE00").at("a"), "\xF0\x9F\x98\x80");
  EXPECT_EQ(detail::parseJavaProperties("a=x\\uD800y").at("a"), "x\xEF\xBF\xBDy");
  EXPECT_EQ(detail::parseJavaProperties("a=\\uDE00").at("a"), "\xEF\xBF\xBD");
  EXPECT_EQ(detail::parseJavaProperties("a=\\uD800\\uD83D\\uDE00").at("a"),
            "\xEF\xBF\xBD\xF0\x9F\x98\x80");
  EXPECT_EQ(detail::parseJavaProperties("a=\\uD800").at("a"), "\xEF\xBF\xBD");
  // Bytes that are not strict UTF-8 (an encoded surrogate, an overlong '/', a lead byte beyond
  // U+10FFFF) make the text ISO-8859-1: each byte its own character.
  EXPECT_EQ(detail::parseJavaProperties("a=\xED\xA0\x80").at("a"), "\xC3\xAD\xC2\xA0\xC2\x80");
  EXPECT_EQ(detail::parseJavaProperties("a=\xC0\xAF").at("a"), "\xC3\x80\xC2\xAF");
  EXPECT_EQ(detail::parseJavaProperties("a=\xF5\x80\x80\x80").at("a"),
            "\xC3\xB5\xC2\x80\xC2\x80\xC2\x80");
}

// ---------------------------------------------------------------------------------------------
// Debian's Sweet Home 3D furniture (package sweethome3d-furniture)
// ---------------------------------------------------------------------------------------------
class SweetHome3DTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (fs::is_directory("/usr/share/sweethome3d/furniture"))
      catalog_ = makeCatalog({"sweethome3d", {}});
  }
  static void TearDownTestSuite() { catalog_.reset(); }
  void SetUp() override {
    if (!catalog_) GTEST_SKIP() << "sweethome3d-furniture is not installed";
  }
  static std::shared_ptr<const ObjectCatalog> catalog_;
};
std::shared_ptr<const ObjectCatalog> SweetHome3DTest::catalog_;

TEST_F(SweetHome3DTest, IndexesEveryItemWithUniqueSortedIds) {
  EXPECT_EQ(catalog_->sourceName(), "sweethome3d");
  const auto& objects = catalog_->objects();
  EXPECT_GE(objects.size(), 800u);
  std::set<std::string> ids;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    EXPECT_TRUE(ids.insert(objects[i].id).second) << "duplicate id " << objects[i].id;
    if (i > 0) {
      EXPECT_LT(objects[i - 1].id, objects[i].id);
    }
    EXPECT_FALSE(objects[i].name.empty());
    EXPECT_FALSE(objects[i].category.empty());
    EXPECT_FALSE(objects[i].license.empty());
  }
  EXPECT_GE(catalog_->idsInCategory("chair").size(), 50u);
  EXPECT_GE(catalog_->idsInCategory("table").size(), 50u);
  const auto categories = catalog_->categories();
  EXPECT_TRUE(std::is_sorted(categories.begin(), categories.end()));
  EXPECT_NE(std::find(categories.begin(), categories.end(), "lamp"), categories.end());
  EXPECT_EQ(catalog_->find("no such id"), nullptr);
}

TEST_F(SweetHome3DTest, OakChairLoadsZUpFrontXInMetres) {
  const ObjectInfo* oak = catalog_->find(kOakChairId);
  ASSERT_NE(oak, nullptr);
  EXPECT_EQ(oak->name, "Oak chair");
  EXPECT_EQ(oak->category, "chair");
  EXPECT_EQ(oak->source_category, "Living room");
  EXPECT_EQ(oak->creator, "Doug C");
  EXPECT_EQ(oak->license, "Public domain");
  EXPECT_TRUE(oak->dimensions_m.isApprox(Eigen::Vector3f(0.491f, 0.612f, 1.178f), 1e-4f));

  const Mesh mesh = catalog_->loadMesh(kOakChairId);
  EXPECT_NEAR(static_cast<double>(mesh.triangleCount()), 31800.0, 300.0);
  // Catalogue size: depth along x (front +x), width along y, height along z.
  const Eigen::Vector3f size = boundingBox(mesh).sizes();
  EXPECT_NEAR(size.x(), 0.612f, 0.01f);
  EXPECT_NEAR(size.y(), 0.491f, 0.01f);
  EXPECT_NEAR(size.z(), 1.178f, 0.01f);
  // Oak texture times a brown diffuse colour: red over green over blue.
  Eigen::Vector3f mean = Eigen::Vector3f::Zero();
  for (const auto& c : mesh.colors) mean += c;
  mean /= static_cast<float>(mesh.colors.size());
  EXPECT_GT(mean.x(), mean.y());
  EXPECT_GT(mean.y(), mean.z());
}

TEST_F(SweetHome3DTest, LibraryNormalisesCachesAndSimplifies) {
  constexpr std::size_t kBudget = 2000;
  ObjectLibrary library(catalog_, kBudget);
  const auto model = library.get(kOakChairId);
  EXPECT_EQ(model->info.id, kOakChairId);
  const Eigen::AlignedBox3f box = boundingBox(model->full);
  EXPECT_NEAR(box.diagonal().norm(), 1.0f, 1e-4f);
  EXPECT_LT(box.center().norm(), 1e-4f);
  EXPECT_GT(model->full.triangleCount(), kBudget);
  EXPECT_LE(model->render.triangleCount(), kBudget);
  EXPECT_GT(model->render.triangleCount(), 0u);
  EXPECT_EQ(library.get(kOakChairId), model);  // cached

  ObjectLibrary full_only(catalog_, 0);
  const auto unsimplified = full_only.get(kOakChairId);
  EXPECT_EQ(unsimplified->render.triangleCount(), unsimplified->full.triangleCount());
}

// ---------------------------------------------------------------------------------------------
// Mesh folders
// ---------------------------------------------------------------------------------------------
using MeshFolderTest = TempDirTest;

// A box 0.2 wide (x), 1 tall (y), 0.4 deep (z, from -0.4 to 0), material `material`.
std::string boxObj(const std::string& mtllib, const std::string& material) {
  std::string obj = mtllib.empty() ? "" : "mtllib " + mtllib + "\n";
  for (int i = 0; i < 8; ++i)
    obj += "v " + std::string(i & 1 ? "0.2" : "0") + (i & 2 ? " 1" : " 0") +
           (i & 4 ? " -0.4" : " 0") + "\n";
  obj += "vt 0.25 0.25\nvt 0.75 0.25\nvt 0.75 0.75\n";
  if (!material.empty()) obj += "usemtl " + material + "\n";
  // Six quads (triangulated by the loader) and one line that must be dropped.
  const int quads[6][4] = {{1, 2, 4, 3}, {5, 7, 8, 6}, {1, 5, 6, 2},
                           {3, 4, 8, 7}, {1, 3, 7, 5}, {2, 6, 8, 4}};
  for (const auto& q : quads)
    obj += "f " + std::to_string(q[0]) + "/1 " + std::to_string(q[1]) + "/2 " +
           std::to_string(q[2]) + "/3 " + std::to_string(q[3]) + "/1\n";
  obj += "l 1 8\n";
  return obj;
}

TEST_F(MeshFolderTest, ScansShapeNetLayoutAndLooseFiles) {
  write("03001627/abc123/models/model_normalized.obj", boxObj("model_normalized.mtl", "red"));
  write("03001627/abc123/models/model_normalized.mtl", "newmtl red\nKd 1 0 0\n");
  write("03001627/abc123/models/model_normalized.json", "{}");  // not a mesh
  // Textured: a uniform green 4x4 PNG times a white diffuse colour.
  write("Cups/tex_cup.obj", boxObj("tex_cup.mtl", "textured"));
  write("Cups/tex_cup.mtl", "newmtl textured\nKd 1 1 1\nmap_Kd textures/green.png\n");
  fs::create_directories(dir_ / "Cups/textures");
  cv::imwrite((dir_ / "Cups/textures/green.png").string(),
              cv::Mat(4, 4, CV_8UC3, cv::Scalar(0, 255, 0)));
  write("Mugs/Blue.PLY",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 0 0 255\n1 0 0 0 0 255\n0 1 0 0 0 255\n3 0 1 2\n");

  std::unique_ptr<ObjectCatalog> catalog = makeCatalog({"folder", {dir_.string()}});
  EXPECT_EQ(catalog->sourceName(), "folder");
  ASSERT_EQ(catalog->objects().size(), 3u);
  const ObjectInfo* shapenet = catalog->find("03001627/abc123");
  ASSERT_NE(shapenet, nullptr);
  EXPECT_EQ(shapenet->category, "chair");
  EXPECT_EQ(shapenet->source_category, "03001627");
  const ObjectInfo* cup = catalog->find("Cups/tex_cup.obj");
  ASSERT_NE(cup, nullptr);
  EXPECT_EQ(cup->category, "cups");
  EXPECT_EQ(cup->source_category, "Cups");
  ASSERT_NE(catalog->find("Mugs/Blue.PLY"), nullptr);
  EXPECT_EQ(catalog->idsInCategory("mugs"), std::vector<std::string>{"Mugs/Blue.PLY"});

  // ShapeNet: y up, front -z -> z up, front +x; Kd red.
  const Mesh chair = catalog->loadMesh("03001627/abc123");
  EXPECT_EQ(chair.triangleCount(), 12u);
  const Eigen::AlignedBox3f chair_box = boundingBox(chair);
  EXPECT_TRUE(chair_box.min().isApprox(Eigen::Vector3f(0.0f, -0.2f, 0.0f), 1e-5f));
  EXPECT_TRUE(chair_box.max().isApprox(Eigen::Vector3f(0.4f, 0.0f, 1.0f), 1e-5f));
  for (const auto& c : chair.colors) EXPECT_TRUE(c.isApprox(Eigen::Vector3f(1, 0, 0)));

  // Other files: y up, front +z; texture sampled into the vertex colours.
  const Mesh textured = catalog->loadMesh("Cups/tex_cup.obj");
  const Eigen::AlignedBox3f cup_box = boundingBox(textured);
  EXPECT_TRUE(cup_box.min().isApprox(Eigen::Vector3f(-0.4f, 0.0f, 0.0f), 1e-5f));
  EXPECT_TRUE(cup_box.max().isApprox(Eigen::Vector3f(0.0f, 0.2f, 1.0f), 1e-5f));
  for (const auto& c : textured.colors) EXPECT_TRUE(c.isApprox(Eigen::Vector3f(0, 1, 0)));

  const Mesh blue = catalog->loadMesh("Mugs/Blue.PLY");
  EXPECT_EQ(blue.triangleCount(), 1u);
  for (const auto& c : blue.colors) EXPECT_TRUE(c.isApprox(Eigen::Vector3f(0, 0, 1)));

  // Concurrent first requests all get the one cached model.
  ObjectLibrary library(std::shared_ptr<const ObjectCatalog>(std::move(catalog)), 0);
  std::vector<std::shared_ptr<const ObjectModel>> models(4);
  std::vector<std::thread> threads;
  for (auto& model : models)
    threads.emplace_back([&library, &model] { model = library.get("03001627/abc123"); });
  for (auto& thread : threads) thread.join();
  for (const auto& model : models) EXPECT_EQ(model, library.get("03001627/abc123"));
  const auto& lookup = library.catalog();

  // Ids are looked up, never opened as paths.
  expectThrowMentioning<InvalidArgumentError>([&] { lookup.loadMesh("Cups/../Cups/tex_cup.obj"); },
                                              "Cups/../Cups/tex_cup.obj");
  EXPECT_THROW(lookup.loadMesh((dir_ / "Cups/tex_cup.obj").string()), InvalidArgumentError);
}

TEST_F(MeshFolderTest, BrokenFilesRaiseCatalogErrorsNamingThem) {
  const std::string empty = write("junk/empty.obj", "");
  const std::string truncated = write("junk/truncated.obj", "v 0 0 0\nv 1 0 0\nv 0 1");
  const std::string garbage = write("junk/garbage.obj", std::string("\x00\xff\x13garbage\n", 11));
  const std::string bad_index = write("junk/bad_index.obj", "v 0 0 0\nv 1 0 0\nf 1 2 9\n");
  const auto catalog = makeMeshFolderCatalog(dir_.string());
  ASSERT_EQ(catalog->objects().size(), 4u);
  expectThrowMentioning<CatalogError>([&] { catalog->loadMesh("junk/empty.obj"); }, empty);
  expectThrowMentioning<CatalogError>([&] { catalog->loadMesh("junk/truncated.obj"); }, truncated);
  expectThrowMentioning<CatalogError>([&] { catalog->loadMesh("junk/garbage.obj"); }, garbage);
  expectThrowMentioning<CatalogError>([&] { catalog->loadMesh("junk/bad_index.obj"); }, bad_index);

  // The library passes catalogue errors through and rejects unknown ids.
  ObjectLibrary library(std::shared_ptr<const ObjectCatalog>(makeMeshFolderCatalog(dir_.string())),
                        100);
  expectThrowMentioning<CatalogError>([&] { library.get("junk/empty.obj"); }, empty);
  expectThrowMentioning<InvalidArgumentError>([&] { library.get("nope"); }, "'nope'");
}

TEST(AxisConversionTest, ProperRotations) {
  for (const Eigen::Matrix3f& r :
       {detail::worldFromYUpFrontZ(), detail::worldFromYUpFrontMinusZ()}) {
    EXPECT_TRUE((r * r.transpose()).isApprox(Eigen::Matrix3f::Identity()));
    EXPECT_FLOAT_EQ(r.determinant(), 1.0f);
    EXPECT_TRUE((r * Eigen::Vector3f::UnitY()).isApprox(Eigen::Vector3f::UnitZ()));  // y up -> z up
  }
  EXPECT_TRUE(
      (detail::worldFromYUpFrontZ() * Eigen::Vector3f::UnitZ()).isApprox(Eigen::Vector3f::UnitX()));
  EXPECT_TRUE((detail::worldFromYUpFrontMinusZ() * -Eigen::Vector3f::UnitZ())
                  .isApprox(Eigen::Vector3f::UnitX()));
  EXPECT_EQ(detail::normalizePath("a\\b/./c/../d//e.png"), "a/b/d/e.png");
  EXPECT_EQ(detail::normalizePath("/x/../../y"), "/y");
}

// ---------------------------------------------------------------------------------------------
// Errors of the factories
// ---------------------------------------------------------------------------------------------
using CatalogErrorsTest = TempDirTest;

TEST_F(CatalogErrorsTest, CorruptSh3fIsNamed) {
  const std::string sh3f = write("Broken.sh3f", "PK\x03\x04 definitely not a zip archive");
  expectThrowMentioning<CatalogError>([&] { makeSweetHome3DCatalog({sh3f}); }, sh3f);
  expectThrowMentioning<CatalogError>([&] { makeCatalog({"sweethome3d", {dir_.string()}}); }, sh3f);
  const std::string missing = (dir_ / "missing.sh3f").string();
  expectThrowMentioning<CatalogError>([&] { makeSweetHome3DCatalog({missing}); }, missing);
}

TEST_F(CatalogErrorsTest, BadOptionsAreRejected) {
  expectThrowMentioning<InvalidArgumentError>(
      [] {
        makeCatalog({"shapenet", {}});
      },
      "embedded, sweethome3d, folder");
  EXPECT_THROW(makeCatalog({"folder", {}}), InvalidArgumentError);
  EXPECT_THROW(makeCatalog({"folder", {dir_.string(), dir_.string()}}), InvalidArgumentError);
  const std::string missing = (dir_ / "no_such_folder").string();
  expectThrowMentioning<CatalogError>([&] { makeCatalog({"folder", {missing}}); }, missing);
  EXPECT_THROW(ObjectLibrary(nullptr, 0), InvalidArgumentError);
}

}  // namespace
}  // namespace occlusion_env
