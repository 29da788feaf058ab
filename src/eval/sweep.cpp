#include "occlusion_env/eval/sweep.hpp"

#include <cmath>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace eval {

std::vector<double> sweepStartAzimuths() {
  const double first = -M_PI / 32.0;
  const double step = M_PI / 208.0;
  // Integer count avoids accumulating the step: (pi/16) / (pi/208) = 13 values.
  const int count = static_cast<int>(std::ceil((M_PI / 16.0) / step - 1e-9));
  std::vector<double> azimuths;
  for (int k = 0; k < count; ++k) azimuths.push_back(first + k * step);
  return azimuths;
}

SceneSet sweepSceneSet(const std::string& preset, const std::string& source) {
  if (preset != "two_chairs" && preset != "two_tables") {
    throw InvalidArgumentError("sweep preset must be two_chairs or two_tables, got " +
                               quoted(preset));
  }
  SceneSet set;
  set.name = "sweep_" + preset;
  set.description = "start-azimuth sweep of the " + preset + " preset";
  set.source = source;
  set.preset = preset;
  set.num_objects = 2;
  set.start_azimuth_rad = 0.0;
  set.start_elevation_rad = 0.0;
  set.seeds = {kSweepSeed};
  return set;
}

}  // namespace eval
}  // namespace occlusion_env
