#include "occlusion_env/common/text_file.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace occlusion_env {
namespace {

[[noreturn]] void cannotWrite(const std::string& path, int error_number) {
  throw std::runtime_error(
      "cannot write " + path +
      (error_number != 0 ? ": " + std::string(std::strerror(error_number)) : std::string()));
}

void writeText(const std::string& path, const std::string& text, std::ios::openmode mode) {
  errno = 0;
  std::ofstream out(path, mode);
  if (!out) cannotWrite(path, errno);
  out << text;
  out.close();  // the last buffered bytes reach the disk here, and may fail here
  if (!out) cannotWrite(path, errno);
}

}  // namespace

void writeTextFile(const std::string& path, const std::string& text) {
  writeText(path, text, std::ios::out | std::ios::trunc);
}

void appendTextFile(const std::string& path, const std::string& text) {
  writeText(path, text, std::ios::out | std::ios::app);
}

void replaceTextFile(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tmp";
  writeTextFile(temporary, text);
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    const int rename_error = error.value();
    std::filesystem::remove(temporary, error);  // best effort: the rename's error is the one told
    cannotWrite(path, rename_error);
  }
}

}  // namespace occlusion_env
