#include "sgslam/common/se3.h"

#include <cmath>

namespace sgslam {

Eigen::Matrix3d Hat(const Eigen::Vector3d& a) {
  Eigen::Matrix3d m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

namespace so3 {

Eigen::Quaterniond Exp(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const double half = 0.5 * theta;
  // Taylor expansion of sin(theta/2)/theta keeps precision near zero.
  const double k = theta < 1e-8 ? 0.5 - theta * theta / 48.0 : std::sin(half) / theta;
  return Eigen::Quaterniond(std::cos(half), k * phi.x(), k * phi.y(), k * phi.z()).normalized();
}

Eigen::Vector3d Log(const Eigen::Quaterniond& q_in) {
  Eigen::Quaterniond q = q_in.normalized();
  if (q.w() < 0) q.coeffs() = -q.coeffs();  // the shorter rotation, angle <= pi
  const Eigen::Vector3d v = q.vec();
  const double s = v.norm();
  if (s < 1e-8) return (2.0 / q.w()) * v;  // theta ~ 2 s / w
  const double theta = 2.0 * std::atan2(s, q.w());
  return (theta / s) * v;
}

Eigen::Matrix3d LeftJacobian(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d W = Hat(phi);
  if (theta < 1e-6) return Eigen::Matrix3d::Identity() + 0.5 * W + W * W / 6.0;
  const double t2 = theta * theta;
  return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / t2 * W +
         (theta - std::sin(theta)) / (t2 * theta) * W * W;
}

Eigen::Matrix3d LeftJacobianInverse(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d W = Hat(phi);
  if (theta < 1e-6) return Eigen::Matrix3d::Identity() - 0.5 * W + W * W / 12.0;
  const double half = 0.5 * theta;
  const double cot_half = std::cos(half) / std::sin(half);
  return Eigen::Matrix3d::Identity() - 0.5 * W + (1.0 - half * cot_half) / (theta * theta) * W * W;
}

}  // namespace so3

SE3 SE3::Exp(const Vector6d& xi) {
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d phi = xi.tail<3>();
  return SE3(so3::Exp(phi), so3::LeftJacobian(phi) * rho);
}

Vector6d SE3::Log() const {
  Vector6d xi;
  const Eigen::Vector3d phi = so3::Log(q_);
  xi.head<3>() = so3::LeftJacobianInverse(phi) * t_;
  xi.tail<3>() = phi;
  return xi;
}

Eigen::Matrix4d SE3::matrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = rotation();
  m.topRightCorner<3, 1>() = t_;
  return m;
}

}  // namespace sgslam
