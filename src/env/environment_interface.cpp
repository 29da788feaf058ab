#include "occlusion_env/env/environment_interface.hpp"

#include <algorithm>
#include <cmath>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

Action cameraMoveFor(const Action& action, double step_size_rad, bool normalize) {
  if (!std::isfinite(action.d_azimuth_rad) || !std::isfinite(action.d_elevation_rad)) {
    throw InvalidArgumentError("action must be finite");
  }
  Action move = action;
  // Scale by the larger component first, so that neither huge nor subnormal actions over- or
  // underflow on the way to their length.
  const double largest = std::max(std::abs(action.d_azimuth_rad), std::abs(action.d_elevation_rad));
  if (largest > 0.0) {
    const double unit_azimuth = action.d_azimuth_rad / largest;
    const double unit_elevation = action.d_elevation_rad / largest;
    const double unit_length = std::hypot(unit_azimuth, unit_elevation);  // in [1, sqrt 2]
    const double length = largest * unit_length;                          // may be inf
    if (normalize || length > step_size_rad) {
      move.d_azimuth_rad = unit_azimuth / unit_length * step_size_rad;
      move.d_elevation_rad = unit_elevation / unit_length * step_size_rad;
    }
  }
  return move;
}

RigObservation rigObservationOf(const Observation& observation, const StepInfo& info) {
  return {observation.rgb,         observation.depth, info.intrinsics, info.pose,
          info.world_from_optical, info.last_action,  info.step_index};
}

RigObservation rigObservationOf(const StepResult& result) {
  if (result.observation == nullptr) throw InvalidStateError("a step result without observation");
  return rigObservationOf(*result.observation, result.info);
}

PrivilegedObservation EnvironmentInterface::privilegedObservation() {
  throw InvalidStateError(describe() +
                          " offers no privileged observation (masks and true occlusion: only an "
                          "in-process simulator can)");
}

GradientResult EnvironmentInterface::occlusionGradient() {
  throw InvalidStateError(describe() + " offers no occlusion gradient (only a simulator can)");
}

}  // namespace occlusion_env
