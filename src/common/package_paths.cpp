#include "occlusion_env/common/package_paths.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace occlusion_env {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPackageName = "occlusion_env";

bool isFile(const fs::path& path) {
  std::error_code error;
  return fs::is_regular_file(path, error);
}

bool isDirectory(const fs::path& path) {
  std::error_code error;
  return fs::is_directory(path, error);
}

bool samePath(const fs::path& a, const fs::path& b) {
  std::error_code error;
  return fs::equivalent(a, b, error);
}

/// `binary`'s install prefix: the folder `levels` above the folder that holds it.
fs::path prefixOf(const std::string& binary, int levels) {
  fs::path prefix = fs::path(binary).parent_path();
  for (int i = 0; i < levels; ++i) prefix = prefix.parent_path();
  return prefix;
}

struct Search {
  const PackageSearch& inputs;
  std::string looked_at;  // one line per place, for the error

  /// The share directory under the prefix of `binary` (described as `what`), or "".
  std::string underPrefixOf(const std::string& binary, int levels, const std::string& what) {
    if (binary.empty()) return "";
    const fs::path prefix = prefixOf(binary, levels);
    const fs::path share = prefix / "share" / kPackageName;
    if (isFile(share / "package.xml")) return share.string();
    looked_at +=
        "\n  " + share.string() + " (the prefix of " + what + " " + binary + "): no package.xml";
    if (inputs.devel_prefix.empty() || !samePath(prefix, inputs.devel_prefix)) return "";
    const fs::path source = inputs.source_directory;
    if (isFile(source / "package.xml")) return source.string();
    looked_at += "\n  " + source.string() + " (the source tree of the devel space " +
                 inputs.devel_prefix + "): no package.xml";
    return "";
  }
};

}  // namespace

std::string findShareDirectory(const PackageSearch& inputs) {
  if (inputs.has_override) {
    if (isDirectory(inputs.override_dir)) return inputs.override_dir;
    throw PackageFileError(std::string(kShareDirectoryVariable) + "=" + inputs.override_dir +
                           " is not a directory (it names the share directory of " + kPackageName +
                           ", the folder with package.xml, models/ and scripts/)");
  }
  Search search{inputs, ""};
  for (const std::string& found :
       {search.underPrefixOf(inputs.library_file, 1, "the library"),
        search.underPrefixOf(inputs.executable_file, 2, "the program")}) {
    if (!found.empty()) return found;
  }
  throw PackageFileError(
      std::string("cannot find the share directory of ") + kPackageName +
      " (package.xml, models/, scripts/, config/); looked at:" + search.looked_at + "\nSet " +
      kShareDirectoryVariable + " to that directory (doc/INSTALL.md).");
}

PackageSearch processPackageSearch() {
  PackageSearch search;
  if (const char* value = std::getenv(kShareDirectoryVariable)) {
    search.has_override = true;
    search.override_dir = value;
  }
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&findShareDirectory), &info) != 0 && info.dli_fname) {
    std::error_code error;
    const fs::path library = fs::canonical(info.dli_fname, error);
    if (!error) search.library_file = library.string();
  }
  std::error_code error;
  const fs::path executable = fs::read_symlink("/proc/self/exe", error);
  if (!error) search.executable_file = executable.string();
  search.devel_prefix = OCCLUSION_ENV_DEVEL_PREFIX;
  search.source_directory = OCCLUSION_ENV_SOURCE_DIR;
  return search;
}

std::string packageShareDirectory() {
  return findShareDirectory(processPackageSearch());
}

}  // namespace occlusion_env
