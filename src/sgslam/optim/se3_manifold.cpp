#include "sgslam/optim/se3_manifold.h"

#include <Eigen/Core>

namespace sgslam::optim {
namespace {
using RowMajor76 = Eigen::Matrix<double, 7, 6, Eigen::RowMajor>;
using RowMajor67 = Eigen::Matrix<double, 6, 7, Eigen::RowMajor>;
}  // namespace

void PoseToParams(const SE3& T, double* x) {
  Eigen::Map<Eigen::Quaterniond> q(x);
  Eigen::Map<Eigen::Vector3d> t(x + 4);
  q = T.quaternion();
  t = T.translation();
}

SE3 ParamsToPose(const double* x) {
  return SE3(Eigen::Map<const Eigen::Quaterniond>(x), Eigen::Map<const Eigen::Vector3d>(x + 4));
}

bool SE3LeftManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  const Vector6d xi = Eigen::Map<const Vector6d>(delta);
  PoseToParams(SE3::Exp(xi) * ParamsToPose(x), x_plus_delta);
  return true;
}

bool SE3LeftManifold::PlusJacobian(const double* x, double* jacobian) const {
  // Exp(delta) * (q, t) = (q_d (x) q, R_d t + V(phi) rho). At delta = 0, with
  // q_d = (phi/2, 1): d vec(q')/d phi = (qw I - [qv]x)/2, d qw'/d phi = -qv^T/2,
  // d t'/d rho = I, d t'/d phi = -[t]x.
  const Eigen::Map<const Eigen::Vector3d> qv(x);
  const double qw = x[3];
  const Eigen::Map<const Eigen::Vector3d> t(x + 4);
  Eigen::Map<RowMajor76> J(jacobian);
  J.setZero();
  J.block<3, 3>(0, 3) = 0.5 * (qw * Eigen::Matrix3d::Identity() - Hat(qv));
  J.block<1, 3>(3, 3) = -0.5 * qv.transpose();
  J.block<3, 3>(4, 0).setIdentity();
  J.block<3, 3>(4, 3) = -Hat(t);
  return true;
}

bool SE3LeftManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Eigen::Map<Vector6d> out(y_minus_x);
  out = (ParamsToPose(y) * ParamsToPose(x).Inverse()).Log();
  return true;
}

bool SE3LeftManifold::MinusJacobian(const double* x, double* jacobian) const {
  // Near y = x: phi ~ 2 vec(q_y (x) q^*) and rho ~ t_y - R(q_y) R^T t; the
  // rotation of a = R^T t by q_y is differentiated in the formula Eigen uses,
  // a + 2 w (v x a) + 2 v x (v x a). The product with PlusJacobian is I6.
  const Eigen::Map<const Eigen::Vector3d> qv(x);
  const double qw = x[3];
  const Eigen::Map<const Eigen::Vector3d> t(x + 4);
  const Eigen::Vector3d a = Eigen::Map<const Eigen::Quaterniond>(x).conjugate() * t;
  Eigen::Map<RowMajor67> J(jacobian);
  J.setZero();
  J.block<3, 3>(3, 0) = 2.0 * (qw * Eigen::Matrix3d::Identity() + Hat(qv));
  J.block<3, 1>(3, 3) = -2.0 * qv;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  J.block<3, 3>(0, 0) = 2.0 * qw * Hat(a) - 2.0 * (qv.dot(a) * I + qv * a.transpose() - 2.0 * a * qv.transpose());
  J.block<3, 1>(0, 3) = -2.0 * qv.cross(a);
  J.block<3, 3>(0, 4) = I;
  return true;
}

}  // namespace sgslam::optim
