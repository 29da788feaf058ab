// Copies of libOSMesa, one per rendering thread, so that renderers on different threads do not
// take turns.
//
// Every OSMesa context of one loaded libOSMesa shares one llvmpipe screen, and that screen's
// rasteriser takes one scene at a time under a lock (Mesa 22.3, lp_setup.c:
// lp_setup_rasterize_scene holds screen->rast_mutex around lp_rast_queue_scene; with
// LP_NUM_THREADS=0 the calling thread rasterises the whole scene inside it). Two environments on
// two threads therefore shaded their fragments one after the other. A second copy of the same
// library file, loaded from memory (memfd) with RTLD_LOCAL, has its own screen, rasteriser and
// lock. The gl* calls need no change: libOSMesa's entry points dispatch through libglapi's
// per-thread current context, which the copy that made a context current has set; only the
// context calls (create, make current, destroy) go to the copy that owns the context.
//
// The first thread with renderers gets the library the process links against; a thread that
// renders while others do gets a copy that no other live thread holds (loaded on demand, kept
// until the process ends). A single-threaded program never loads a copy. Setting
// OCCLUSION_ENV_SHARED_LLVMPIPE=1 turns the copies off (every thread on the linked library).
#pragma once

#include <GL/osmesa.h>

#include <thread>

namespace occlusion_env {
namespace osmesa {

/// The context entry points of one loaded copy of libOSMesa.
struct OsMesaLibrary {
  decltype(&OSMesaCreateContextAttribs) create_context_attribs = nullptr;
  decltype(&OSMesaMakeCurrent) make_current = nullptr;
  decltype(&OSMesaGetCurrentContext) get_current_context = nullptr;
  decltype(&OSMesaDestroyContext) destroy_context = nullptr;
};

/// The copy that `thread`'s renderers use, held for as long as the lease lives (one lease per
/// renderer; a thread keeps its copy while it has any). Thread-safe.
class OsMesaLease {
 public:
  explicit OsMesaLease(std::thread::id thread);
  ~OsMesaLease();
  OsMesaLease(const OsMesaLease&) = delete;
  OsMesaLease& operator=(const OsMesaLease&) = delete;

  const OsMesaLibrary& library() const { return *library_; }

 private:
  std::thread::id thread_;
  const OsMesaLibrary* library_;
};

/// Makes `context` of `library` current on the calling thread (unless it is): first releases a
/// context another copy made current here. False when OSMesaMakeCurrent fails.
bool makeCurrent(const OsMesaLibrary& library, OSMesaContext context, void* buffer, int width,
                 int height);

/// Destroys `context` of `library` from any thread, releasing first whatever context is current
/// on the calling thread if another copy made it current.
void destroyContext(const OsMesaLibrary& library, OSMesaContext context);

}  // namespace osmesa
}  // namespace occlusion_env
