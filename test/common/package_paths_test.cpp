#include "occlusion_env/common/package_paths.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "common/temporary_dir.hpp"

namespace occlusion_env {
namespace {

namespace fs = std::filesystem;

/// A scratch folder holding a fake install prefix, devel space and source tree.
class PackagePathsTest : public TemporaryDirTest {
 protected:
  void SetUp() override {
    TemporaryDirTest::SetUp();
    fs::create_directories(dir_ / "install/lib/occlusion_env");
    fs::create_directories(dir_ / "devel/lib/occlusion_env");
    fs::create_directories(dir_ / "devel/share/occlusion_env/cmake");  // as catkin makes it
    fs::create_directories(dir_ / "source");
    std::ofstream(dir_ / "source/package.xml") << "<package/>\n";
  }

  void installShare() {
    fs::create_directories(dir_ / "install/share/occlusion_env");
    std::ofstream(dir_ / "install/share/occlusion_env/package.xml") << "<package/>\n";
  }
  /// The inputs of a process whose library and program are under `prefix`.
  PackageSearch searchFrom(const std::string& prefix) const {
    PackageSearch search;
    search.library_file = (dir_ / prefix / "lib/libocclusion_env_core.so").string();
    search.executable_file = (dir_ / prefix / "lib/occlusion_env/occlusion_agents").string();
    search.devel_prefix = (dir_ / "devel").string();
    search.source_directory = (dir_ / "source").string();
    return search;
  }
  std::string path(const std::string& relative) const { return (dir_ / relative).string(); }
};

TEST_F(PackagePathsTest, InstalledProgramFindsTheShareDirectoryOfItsPrefix) {
  installShare();
  EXPECT_EQ(findShareDirectory(searchFrom("install")), path("install/share/occlusion_env"));
  // A program of the install space that links another copy of the library: its own prefix.
  PackageSearch program_only = searchFrom("install");
  program_only.library_file = path("elsewhere/lib/libocclusion_env_core.so");
  EXPECT_EQ(findShareDirectory(program_only), path("install/share/occlusion_env"));
}

TEST_F(PackagePathsTest, DevelSpaceFallsBackToTheSourceTree) {
  EXPECT_EQ(findShareDirectory(searchFrom("devel")), path("source"));
}

TEST_F(PackagePathsTest, InstalledProgramNeverReadsTheSourceTree) {
  // No share directory in the install prefix: the source tree (which has package.xml) must not
  // stand in for it, and the error names each place looked at.
  try {
    findShareDirectory(searchFrom("install"));
    FAIL() << "an install space without its share directory was accepted";
  } catch (const PackageFileError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(path("install/share/occlusion_env") + " (the prefix of the library"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find(path("install/share/occlusion_env") + " (the prefix of the program"),
              std::string::npos)
        << message;
    EXPECT_EQ(message.find(path("source")), std::string::npos) << message;
    EXPECT_NE(message.find(kShareDirectoryVariable), std::string::npos) << message;
  }
}

TEST_F(PackagePathsTest, VariableOverridesEverySearch) {
  installShare();
  PackageSearch search = searchFrom("install");
  search.has_override = true;
  search.override_dir = path("source");
  EXPECT_EQ(findShareDirectory(search), path("source"));
  search.override_dir = path("no_such_dir");
  try {
    findShareDirectory(search);
    FAIL() << "a missing override directory was accepted";
  } catch (const PackageFileError& error) {
    EXPECT_NE(std::string(error.what())
                  .find(std::string(kShareDirectoryVariable) + "=" + path("no_such_dir")),
              std::string::npos)
        << error.what();
  }
}

TEST(PackagePathsProcessTest, ThisTestOfTheDevelSpaceFindsItsSourceTree) {
  const PackageSearch search = processPackageSearch();
  EXPECT_FALSE(search.library_file.empty());
  EXPECT_FALSE(search.executable_file.empty());
  if (search.has_override) GTEST_SKIP() << kShareDirectoryVariable << " is set";
  EXPECT_TRUE(fs::equivalent(packageShareDirectory(), OCCLUSION_ENV_SOURCE_DIR));
}

}  // namespace
}  // namespace occlusion_env
