// The global OctoMap of the paper's semantic mapping thread (Sec. III-E): a
// ColorOcTree updated incrementally per keyframe by inserting its static depth
// pixels as rays from the camera centre (free space along each ray is cleared, so
// a place a person walked through becomes free again), with the release's sensor
// model (octomap_builder.cpp: kOctoMapProbHit 0.7, kOctoMapProbMiss 0.4, clamping
// kOctoMapClampMin / kOctoMapClampMax 0.12 / 0.97) at semantic.octomap_resolution.
//
// Threading: not thread-safe; owned by the semantic mapping thread, read after it stopped.
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/semantic/cloud.h"
#include "sgslam/semantic/semantic_config.h"

namespace octomap {
class ColorOcTree;
}

namespace sgslam {

class OctoMapBuilder {
 public:
  explicit OctoMapBuilder(const SemanticConfig& config);
  ~OctoMapBuilder();
  OctoMapBuilder(const OctoMapBuilder&) = delete;
  OctoMapBuilder& operator=(const OctoMapBuilder&) = delete;

  // surface_c: static points in the camera frame, whose voxels are hits (with
  // their colour); rays_c: a sparser subset whose rays from the camera centre
  // clear free space (casting every point's ray would cost far more for the same
  // free space at this resolution). T_w_c: the camera pose.
  void Insert(const std::vector<ColoredPoint>& surface_c, const std::vector<ColoredPoint>& rays_c, const SE3& T_w_c);
  // Updates inner nodes and prunes; Write() and the queries need it after inserts.
  void Finalize();
  // Forgets everything (same settings).
  void Clear();
  // The voxel at p_w was observed and its occupancy ended below 0.5.
  bool IsFree(const Eigen::Vector3d& p_w) const;
  // The voxel at p_w was observed and its occupancy ended above 0.5.
  bool IsOccupied(const Eigen::Vector3d& p_w) const;
  double resolution() const;
  std::size_t OccupiedLeaves() const;
  // The occupied leaves: centre (m, world) and side (m) each.
  std::vector<Eigen::Vector4f> OccupiedCells() const;
  // Binary .bt (occupancy only, as octovis and octomap_server read it), atomically.
  // Throws InputError naming the file.
  void Write(const std::filesystem::path& path);

 private:
  SemanticConfig config_;
  std::unique_ptr<octomap::ColorOcTree> tree_;
  bool dirty_ = false;
};

}  // namespace sgslam
