#include "occlusion_env/common/text_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/temporary_dir.hpp"

namespace occlusion_env {
namespace {

namespace fs = std::filesystem;

std::string readAll(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

using TextFileTest = TemporaryDirTest;

TEST_F(TextFileTest, WritesReplacesAndAppends) {
  const std::string path = (dir_ / "log.csv").string();
  writeTextFile(path, "a,b\n");
  writeTextFile(path, "epoch,iou\n");
  EXPECT_EQ(readAll(path), "epoch,iou\n");
  appendTextFile(path, "1,0.5\n");
  appendTextFile((dir_ / "new.csv").string(), "x\n");  // created when missing
  EXPECT_EQ(readAll(path), "epoch,iou\n1,0.5\n");
  EXPECT_EQ(readAll(dir_ / "new.csv"), "x\n");
}

TEST_F(TextFileTest, ReplacingLeavesTheWholeNewFileAndNoTemporary) {
  const std::string path = (dir_ / "checkpoint.json").string();
  replaceTextFile(path, "{\"epoch\": 1}\n");
  replaceTextFile(path, "{\"epoch\": 2}\n");
  EXPECT_EQ(readAll(path), "{\"epoch\": 2}\n");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

// A result written into a folder that is not there (a mistyped --out, a read-only install) must
// stop the tool with the file's name, not vanish while the tool reports it written.
TEST_F(TextFileTest, AFileThatCannotBeWrittenIsAnErrorNamingIt) {
  const std::string missing = (dir_ / "no_such_folder" / "model.check.json").string();
  for (const auto& write : {writeTextFile, appendTextFile, replaceTextFile}) {
    try {
      write(missing, "{}\n");
      ADD_FAILURE() << "no error for " << missing;
    } catch (const std::runtime_error& error) {
      EXPECT_NE(std::string(error.what()).find("no_such_folder"), std::string::npos)
          << error.what();
    }
  }
  EXPECT_FALSE(fs::exists(dir_ / "no_such_folder"));
  // A folder where the file should be: the file cannot be opened, and the error says so.
  fs::create_directories(dir_ / "taken.json");
  EXPECT_THROW(writeTextFile((dir_ / "taken.json").string(), "{}\n"), std::runtime_error);
  EXPECT_THROW(replaceTextFile((dir_ / "taken.json").string(), "{}\n"), std::runtime_error);
}

}  // namespace
}  // namespace occlusion_env
