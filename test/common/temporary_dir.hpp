// Scratch folders for tests, under the system's temporary directory and named after the process
// (and the test), so that two test binaries running at once never share one.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>

namespace occlusion_env {

// `name`_<pid> under the temporary directory, removed if it was there; not created.
inline std::filesystem::path temporaryDir(const std::string& name) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(path);
  return path;
}

// A fixture whose dir_ is an empty folder named after the running test, made before each test and
// removed after it.
class TemporaryDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::replace(test.begin(), test.end(), '/', '_');  // a parameterised test's name has one
    dir_ = temporaryDir("occlusion_env_" + test);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path dir_;
};

}  // namespace occlusion_env
