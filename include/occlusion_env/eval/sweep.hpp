// The paper's start-azimuth sweep (Section 6.2.1, Figure 5): one preset scene (two chairs or two
// tables) started from azimuths over [-pi/32, pi/32) in steps of pi/208.
#pragma once

#include <string>
#include <vector>

#include "occlusion_env/env/scene_set.hpp"

namespace occlusion_env {
namespace eval {

/// The seed that picks the preset's model; outside the training range.
inline constexpr std::uint64_t kSweepSeed = 1'002'000;
inline constexpr int kSweepMaxSteps = 2000;  // the paper's plot limit

/// -pi/32 + k pi/208 for k = 0, 1, ... while below pi/32: 13 azimuths [rad].
std::vector<double> sweepStartAzimuths();

/// The sweep's scene: `preset` ("two_chairs" | "two_tables", else InvalidArgumentError) from
/// `source` (any source with chair and table categories), one seed, elevation 0. Its name is
/// "sweep_<preset>"; the start azimuth is set per episode.
SceneSet sweepSceneSet(const std::string& preset, const std::string& source = "embedded");

}  // namespace eval
}  // namespace occlusion_env
