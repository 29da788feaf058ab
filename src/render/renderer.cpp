#include "occlusion_env/render/renderer.hpp"

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

void Renderer::setBackground(const SceneBackground& background) {
  if (!background.one_sided.empty() || !background.two_sided.empty() || !background.tiled.empty() ||
      !background.lighting.headlight) {
    throw InvalidArgumentError("renderer " + name() + " draws no background and no other light");
  }
}

}  // namespace occlusion_env
