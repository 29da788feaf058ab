// Fixed capacities of the core, named once.
#pragma once

#include <cstddef>

namespace occlusion_env {

/// Most objects one scene may hold: one amodal bit (CV_8UC1 amodal_bits) and one depth target of
/// the renderer each.
constexpr int kMaxSceneObjects = 8;

/// Object pairs i < j of the largest scene: the capacity of the per-pair occlusion figures.
constexpr std::size_t kMaxObjectPairs = kMaxSceneObjects * (kMaxSceneObjects - 1) / 2;

}  // namespace occlusion_env
