// Two-view geometry for creating map points.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "sgslam/camera/camera.h"
#include "sgslam/common/se3.h"

namespace sgslam {

// F_21 such that x2^T F_21 x1 = 0 for pixels x1 in camera 1 and x2 in camera 2,
// from the poses T_1w and T_2w and the shared pinhole intrinsics.
Eigen::Matrix3d FundamentalMatrix(const SE3& T_1w, const SE3& T_2w, const Camera& camera);

// Linear (DLT) triangulation from normalised image rays x = (X/Z, Y/Z, 1) in the
// two cameras. nullopt when the solution is at infinity.
std::optional<Eigen::Vector3d> Triangulate(const Eigen::Vector3d& x1, const Eigen::Vector3d& x2, const SE3& T_1w,
                                           const SE3& T_2w);

}  // namespace sgslam
