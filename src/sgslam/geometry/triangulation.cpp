#include "sgslam/geometry/triangulation.h"

#include <cmath>

#include <Eigen/SVD>

namespace sgslam::geometry {

std::optional<Eigen::Vector3d> Triangulate(const Eigen::Vector3d& x1, const Eigen::Vector3d& x2, const SE3& T_1w,
                                           const SE3& T_2w) {
  Eigen::Matrix<double, 3, 4> P1, P2;
  P1 << T_1w.rotation(), T_1w.translation();
  P2 << T_2w.rotation(), T_2w.translation();
  Eigen::Matrix4d A;
  A.row(0) = x1.x() * P1.row(2) - P1.row(0);
  A.row(1) = x1.y() * P1.row(2) - P1.row(1);
  A.row(2) = x2.x() * P2.row(2) - P2.row(0);
  A.row(3) = x2.y() * P2.row(2) - P2.row(1);
  const Eigen::Vector4d h = Eigen::JacobiSVD<Eigen::Matrix4d>(A, Eigen::ComputeFullV).matrixV().col(3);
  if (std::abs(h(3)) < 1e-12) return std::nullopt;
  return Eigen::Vector3d(h.head<3>() / h(3));
}

}  // namespace sgslam::geometry
