#include "occlusion_env/render/lod_quality.hpp"

#include <algorithm>

namespace occlusion_env {

std::vector<SphericalPose> silhouetteCheckViews() {
  std::vector<SphericalPose> views;
  for (double azimuth : {0.0, 0.8, 1.6, 2.4, 3.1, -0.8, -1.6, -2.4}) {
    views.push_back({azimuth, azimuth > 0.0 ? 0.0 : 0.5});
  }
  return views;
}

double worstSilhouetteIou(Renderer& renderer, const Mesh& full, const Mesh& lod,
                          const SphericalCamera& camera, const std::vector<SphericalPose>& views,
                          RenderBuffers& full_buffers, RenderBuffers& lod_buffers) {
  double worst = 1.0;
  for (const SphericalPose& pose : views) {
    const Eigen::Isometry3d world_from_optical = camera.worldFromOptical(pose);
    renderer.setScene({{&full, Eigen::Isometry3d::Identity()}});
    renderer.render(world_from_optical, full_buffers);
    renderer.setScene({{&lod, Eigen::Isometry3d::Identity()}});
    renderer.render(world_from_optical, lod_buffers);
    const cv::Mat a = full_buffers.amodal_bits != 0, b = lod_buffers.amodal_bits != 0;
    const int united = cv::countNonZero(a | b);
    if (united == 0) continue;
    worst = std::min(worst, static_cast<double>(cv::countNonZero(a & b)) / united);
  }
  return worst;
}

}  // namespace occlusion_env
