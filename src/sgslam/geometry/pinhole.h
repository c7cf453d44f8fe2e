// Pinhole intrinsics, for the solvers that work on undistorted pixels.
#pragma once

#include <Eigen/Core>

namespace sgslam::geometry {

struct Pinhole {
  double fx = 0, fy = 0, cx = 0, cy = 0;  // px

  Eigen::Vector2d Project(const Eigen::Vector3d& p_c) const {
    return {fx * p_c.x() / p_c.z() + cx, fy * p_c.y() / p_c.z() + cy};
  }
};

}  // namespace sgslam::geometry
