#include "osmesa_library.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/sendfile.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace occlusion_env {
namespace osmesa {
namespace {

constexpr std::size_t kMaxCopies = 16;  // besides the linked one; more threads share

struct Copy {
  OsMesaLibrary library;
  int threads = 0;  // live threads holding it
};

struct Pool {
  std::mutex mutex;
  std::vector<std::unique_ptr<Copy>> copies;                 // [0] = the linked library
  std::map<std::thread::id, std::pair<Copy*, int>> holders;  // thread -> copy, leases
  bool shared_only = false;  // OCCLUSION_ENV_SHARED_LLVMPIPE=1, or loading a copy failed
};

// Never destroyed: the copies stay loaded until the process ends (their contexts may outlive any
// static destructor order).
Pool& pool() {
  static Pool* const instance = [] {
    auto* made = new Pool;
    auto linked = std::make_unique<Copy>();
    linked->library = {&OSMesaCreateContextAttribs, &OSMesaMakeCurrent, &OSMesaGetCurrentContext,
                       &OSMesaDestroyContext};
    made->copies.push_back(std::move(linked));
    const char* shared = std::getenv("OCCLUSION_ENV_SHARED_LLVMPIPE");
    made->shared_only = shared != nullptr && std::string(shared) == "1";
    return made;
  }();
  return *instance;
}

// The file of the libOSMesa this process links against.
std::string linkedLibraryPath() {
  Dl_info info{};
  void* symbol = dlsym(RTLD_DEFAULT, "OSMesaCreateContextAttribs");
  if (symbol == nullptr || dladdr(symbol, &info) == 0 || info.dli_fname == nullptr) return {};
  return info.dli_fname;
}

// A private copy of the library: the file copied into an anonymous memory file and loaded from
// there (another inode, so the loader maps it anew instead of returning the loaded one).
std::unique_ptr<Copy> loadCopy(std::string& error) {
  const std::string path = linkedLibraryPath();
  if (path.empty()) {
    error = "cannot find the loaded libOSMesa";
    return nullptr;
  }
  const int source = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  struct stat status {};
  if (source < 0 || fstat(source, &status) != 0) {
    error = "cannot read " + path;
    if (source >= 0) close(source);
    return nullptr;
  }
  const int memory = memfd_create("libOSMesa-copy", MFD_CLOEXEC);
  off_t offset = 0;
  while (memory >= 0 && offset < status.st_size) {
    if (sendfile(memory, source, &offset, status.st_size - offset) <= 0) break;
  }
  close(source);
  if (memory < 0 || offset != status.st_size) {
    error = "cannot copy " + path + " into memory";
    if (memory >= 0) close(memory);
    return nullptr;
  }
  const std::string name = "/proc/self/fd/" + std::to_string(memory);
  void* handle = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL);
  close(memory);  // the mapping stays
  if (handle == nullptr) {
    const char* message = dlerror();
    error = std::string("cannot load a copy of ") + path + ": " + (message ? message : "");
    return nullptr;
  }
  auto copy = std::make_unique<Copy>();
  OsMesaLibrary& library = copy->library;
  library.create_context_attribs = reinterpret_cast<decltype(library.create_context_attribs)>(
      dlsym(handle, "OSMesaCreateContextAttribs"));
  library.make_current =
      reinterpret_cast<decltype(library.make_current)>(dlsym(handle, "OSMesaMakeCurrent"));
  library.get_current_context = reinterpret_cast<decltype(library.get_current_context)>(
      dlsym(handle, "OSMesaGetCurrentContext"));
  library.destroy_context =
      reinterpret_cast<decltype(library.destroy_context)>(dlsym(handle, "OSMesaDestroyContext"));
  if (!library.create_context_attribs || !library.make_current || !library.get_current_context ||
      !library.destroy_context) {
    error = "a copy of " + path + " lacks the OSMesa context functions";
    return nullptr;  // the handle stays open: a half-usable library is never unloaded
  }
  return copy;
}

// A copy no live thread holds: an existing one, a new one, or (at the limit, or when copies
// cannot be loaded) the one the fewest threads hold. Called under the pool's mutex.
Copy* freeCopy(Pool& p) {
  Copy* least = p.copies.front().get();
  for (const auto& copy : p.copies) {
    if (copy->threads == 0) return copy.get();
    if (copy->threads < least->threads) least = copy.get();
  }
  if (p.shared_only || p.copies.size() > kMaxCopies) return least;
  std::string error;
  std::unique_ptr<Copy> loaded = loadCopy(error);
  if (!loaded) {
    std::cerr << "occlusion_env: renderers on different threads share one llvmpipe (" << error
              << "): they rasterise in turn\n";
    p.shared_only = true;
    return least;
  }
  p.copies.push_back(std::move(loaded));
  return p.copies.back().get();
}

// The copy whose context is current on this thread, if this library made one current.
thread_local const OsMesaLibrary* current_library = nullptr;

// Releases the calling thread's current context if a copy other than `library` made it current.
void releaseOtherCopy(const OsMesaLibrary& library) {
  if (current_library != nullptr && current_library != &library) {
    current_library->make_current(nullptr, nullptr, 0, 0, 0);
    current_library = nullptr;
  }
}

}  // namespace

OsMesaLease::OsMesaLease(std::thread::id thread) : thread_(thread) {
  Pool& p = pool();
  const std::lock_guard<std::mutex> lock(p.mutex);
  auto holder = p.holders.find(thread);
  if (holder == p.holders.end()) {
    Copy* copy = freeCopy(p);
    ++copy->threads;
    holder = p.holders.emplace(thread, std::make_pair(copy, 0)).first;
  }
  ++holder->second.second;
  library_ = &holder->second.first->library;
}

OsMesaLease::~OsMesaLease() {
  Pool& p = pool();
  const std::lock_guard<std::mutex> lock(p.mutex);
  auto holder = p.holders.find(thread_);
  if (holder == p.holders.end()) return;
  if (--holder->second.second == 0) {
    --holder->second.first->threads;
    p.holders.erase(holder);
  }
}

bool makeCurrent(const OsMesaLibrary& library, OSMesaContext context, void* buffer, int width,
                 int height) {
  releaseOtherCopy(library);
  if (library.get_current_context() != context &&
      !library.make_current(context, buffer, GL_UNSIGNED_BYTE, width, height)) {
    return false;
  }
  current_library = &library;
  return true;
}

void destroyContext(const OsMesaLibrary& library, OSMesaContext context) {
  releaseOtherCopy(library);
  if (library.get_current_context() == context) {
    library.make_current(nullptr, nullptr, 0, 0, 0);
    current_library = nullptr;
  }
  library.destroy_context(context);
}

}  // namespace osmesa
}  // namespace occlusion_env
