#include "occlusion_env/env/environment_interface.hpp"

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

GradientResult EnvironmentInterface::occlusionGradient() {
  throw InvalidStateError(describe() + " offers no occlusion gradient (only a simulator can)");
}

}  // namespace occlusion_env
