#include "sgslam/eval/semantic_score.h"

#include <cmath>
#include <cstdint>
#include <unordered_set>

#include "sgslam/camera/camera.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/semantic/voxel_cell.h"

namespace sgslam::eval {

CloudTruth ScoreCloud(const SemanticMapper& map, const ImageOf& mask_of) {
  CloudTruth t;
  const Camera& camera = map.camera();
  for (const SemanticMapper::KeyFramePoints& k : map.KeyFrameClouds()) {
    const cv::Mat mask = mask_of(k.keyframe->t);
    if (mask.empty()) continue;
    ++t.keyframes;
    const SE3 T_w_c = k.keyframe->PlacedT_c_w().Inverse();
    for (const ColoredPoint& p : *k.points_c) {
      if (!map.Exported(T_w_c * p.p.cast<double>())) continue;
      const Eigen::Vector2d uv = camera.Distort(camera.Project(p.p.cast<double>()));
      const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
      if (u < 0 || v < 0 || u >= mask.cols || v >= mask.rows) continue;
      ++t.points;
      t.moving += mask.at<std::uint8_t>(v, u) != 0;
    }
  }
  return t;
}

OctoMapTruth ScoreOctoMap(const SemanticMapper& map, const ImageOf& mask_of, const ImageOf& depth_of, int stride) {
  OctoMapTruth t;
  const OctoMapBuilder& octomap = map.octomap();
  const double inv = 1.0 / octomap.resolution();
  const SemanticConfig& c = map.config();
  const double depth_factor = map.camera().config().depth_factor;
  const PixelRays rays(map.camera());
  std::unordered_set<std::uint64_t> moving, static_cells;
  for (const SemanticMapper::KeyFramePoints& k : map.KeyFrameClouds()) {
    const cv::Mat mask = mask_of(k.keyframe->t), depth = depth_of(k.keyframe->t);
    if (mask.empty() || depth.empty() || mask.size() != depth.size() || depth.type() != CV_16UC1) continue;
    ++t.keyframes;
    const SE3 T_w_c = k.keyframe->PlacedT_c_w().Inverse();
    for (int v = 0; v < depth.rows; v += stride) {
      for (int u = 0; u < depth.cols; u += stride) {
        const double z = depth.at<std::uint16_t>(v, u) / depth_factor;
        if (z < c.depth_min || z > c.depth_max) continue;
        const cv::Vec2f& r = rays.at(u, v);
        const Eigen::Vector3d p = T_w_c * Eigen::Vector3d(r[0] * z, r[1] * z, z);
        (mask.at<std::uint8_t>(v, u) != 0 ? moving : static_cells).insert(VoxelCell::Of(p, inv).Key());
      }
    }
  }
  for (std::uint64_t m : moving) {
    // A path cell has no static cell among itself and its 26 neighbours.
    const VoxelCell cell = VoxelCell::FromKey(m);
    bool near_static = false;
    for (int dx = -1; dx <= 1 && !near_static; ++dx) {
      for (int dy = -1; dy <= 1 && !near_static; ++dy) {
        for (int dz = -1; dz <= 1 && !near_static; ++dz) {
          near_static = static_cells.count(cell.Shifted(dx, dy, dz).Key()) != 0;
        }
      }
    }
    if (near_static) continue;
    ++t.path_cells;
    t.occupied += octomap.IsOccupied(cell.Centre(octomap.resolution())) ? 1 : 0;
  }
  return t;
}

}  // namespace sgslam::eval
