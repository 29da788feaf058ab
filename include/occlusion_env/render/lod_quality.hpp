// How well a level-of-detail mesh keeps its object's silhouette: the measure behind the LOD test
// and `occlusion_lod_report`.
#pragma once

#include <vector>

#include "occlusion_env/geometry/camera.hpp"
#include "occlusion_env/render/renderer.hpp"
#include "occlusion_env/scene/mesh.hpp"

namespace occlusion_env {

/// The views the LOD silhouettes are compared from: eight azimuths around the object, those with
/// positive azimuth at elevation 0, the others from 0.5 rad above.
std::vector<SphericalPose> silhouetteCheckViews();

/// Worst intersection over union, over `views`, of the amodal silhouettes of `full` and `lod`
/// placed at the origin and seen by `renderer` from `camera`. 1 when neither covers a pixel.
/// `full_buffers` and `lod_buffers` are scratch images, reused across calls.
double worstSilhouetteIou(Renderer& renderer, const Mesh& full, const Mesh& lod,
                          const SphericalCamera& camera, const std::vector<SphericalPose>& views,
                          RenderBuffers& full_buffers, RenderBuffers& lod_buffers);

}  // namespace occlusion_env
