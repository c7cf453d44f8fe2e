// A cell of a regular voxel grid and its 64-bit hash key, shared by the cloud's
// downsampling, the view-support filter and the OctoMap path score.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

namespace sgslam {

struct VoxelCell {
  std::int64_t x = 0, y = 0, z = 0;

  // inv_voxel = 1 / voxel side.
  static VoxelCell Of(const Eigen::Vector3d& p, double inv_voxel) {
    const auto axis = [inv_voxel](double v) { return static_cast<std::int64_t>(std::floor(v * inv_voxel)); };
    return {axis(p.x()), axis(p.y()), axis(p.z())};
  }
  // 21 bits per axis: +-1e6 voxels, ample for rooms at centimetre voxels.
  std::uint64_t Key() const {
    const auto axis = [](std::int64_t v) { return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1FFFFF; };
    return axis(x) | (axis(y) << 21) | (axis(z) << 42);
  }
  static VoxelCell FromKey(std::uint64_t key) {
    const auto axis = [key](int shift) { return static_cast<std::int64_t>((key >> shift) & 0x1FFFFF) - (1 << 20); };
    return {axis(0), axis(21), axis(42)};
  }
  VoxelCell Shifted(int dx, int dy, int dz) const { return {x + dx, y + dy, z + dz}; }
  Eigen::Vector3d Centre(double voxel) const {
    return Eigen::Vector3d(static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5, static_cast<double>(z) + 0.5) *
           voxel;
  }
};

}  // namespace sgslam
