// A fresh folder under the system's temporary directory, named after the test and the process.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

namespace occlusion_env {
namespace learning {

inline std::filesystem::path temporaryDir(const std::string& name) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(path);
  return path;
}

}  // namespace learning
}  // namespace occlusion_env
