// Where the package's data (models/, scripts/, config/) is at run time, without ROS: in an
// install space (catkin_make install, a release) it is <prefix>/share/occlusion_env; in a
// development build (catkin's devel space) it is the source tree. doc/INSTALL.md explains it.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace occlusion_env {

/// The environment variable that names the share directory; when set, nothing else is searched.
constexpr const char* kShareDirectoryVariable = "OCCLUSION_ENV_SHARE_DIR";

/// The share directory or a file in it cannot be found; the message says where it looked.
class PackageFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What the search looks at; packageShareDirectory() fills it from the running process.
struct PackageSearch {
  bool has_override = false;     // kShareDirectoryVariable is set
  std::string override_dir;      // its value
  std::string library_file;      // this library's file, <prefix>/lib/libocclusion_env_core.so
  std::string executable_file;   // the running program, <prefix>/lib/occlusion_env/<program>
  std::string devel_prefix;      // the catkin devel space this library was built for
  std::string source_directory;  // the source tree it was built from (devel space only)
};

/// The search of packageShareDirectory() on the given inputs (tests give their own).
/// Order: the override; then <prefix>/share/occlusion_env (it must hold package.xml) for the
/// library's and then the executable's prefix; the source tree only when one of those prefixes
/// is the devel space. Throws PackageFileError naming every place it looked.
std::string findShareDirectory(const PackageSearch& search);

/// The search inputs of this process: the variable, this library's file (dladdr), the executable
/// (/proc/self/exe) and the build's devel space and source tree.
PackageSearch processPackageSearch();

/// findShareDirectory(processPackageSearch()): a few file look-ups, not cached.
std::string packageShareDirectory();

}  // namespace occlusion_env
