// The OSMesa (llvmpipe) back end of the Renderer interface: the default of every environment.
#pragma once

#include <memory>

#include "occlusion_env/render/renderer.hpp"

namespace occlusion_env {

/// An off-screen OpenGL 3.3 core renderer on OSMesa (llvmpipe). Its GL context belongs to the
/// thread that creates it; every call must come from that thread. Several may coexist.
///
/// llvmpipe reads its rasteriser thread count (LP_NUM_THREADS) once per process, when the first
/// context is created: the first renderer's options.rasterizer_threads fixes it for the process,
/// and a later renderer asking for another count gets InvalidArgumentError.
///
/// Renderers on different threads at once run on different copies of libOSMesa (one llvmpipe
/// rasteriser each, not one shared under a lock; src/render/osmesa/osmesa_library.hpp);
/// OCCLUSION_ENV_SHARED_LLVMPIPE=1 puts them all on one, as before.
std::unique_ptr<Renderer> makeOsMesaRenderer(const CameraIntrinsics& intrinsics,
                                             const RendererOptions& options = {});

}  // namespace occlusion_env
