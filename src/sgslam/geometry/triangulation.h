// Two-view triangulation, for creating map points.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "sgslam/common/se3.h"

namespace sgslam::geometry {

// Linear (DLT) triangulation from normalised image rays x = (X/Z, Y/Z, 1) in the
// two cameras. nullopt when the solution is at infinity.
std::optional<Eigen::Vector3d> Triangulate(const Eigen::Vector3d& x1, const Eigen::Vector3d& x2, const SE3& T_1w,
                                           const SE3& T_2w);

}  // namespace sgslam::geometry
