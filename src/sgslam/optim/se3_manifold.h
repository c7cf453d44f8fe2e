// SE(3) as a ceres::Manifold with a left-multiplicative perturbation, the pose
// parameterisation of every optimisation problem here (ORB-SLAM2's g2o
// VertexSE3Expmap does the same: T <- Exp(delta) * T).
//
// Ambient layout (7): [qx qy qz qw tx ty tz] — Eigen's quaternion coefficient
// order, so Eigen::Map<Quaterniond>(x) views the rotation in place.
// Tangent (6): delta = [rho; phi], the order of sgslam::SE3::Exp/Log.
// The cost functions return true ambient Jacobians; Ceres chains them with
// PlusJacobian, so J_tangent = J_ambient * PlusJacobian (tested numerically).
#pragma once

#include <ceres/manifold.h>

#include "sgslam/common/se3.h"

namespace sgslam::optim {

inline constexpr int kPoseAmbientSize = 7;
inline constexpr int kPoseTangentSize = 6;

// Copies between SE3 and the 7-double ambient layout.
void PoseToParams(const SE3& T, double* x);
SE3 ParamsToPose(const double* x);

class SE3LeftManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return kPoseAmbientSize; }
  int TangentSize() const override { return kPoseTangentSize; }
  // x_plus_delta = Exp(delta) * x.
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  // 7x6 row-major d Plus(x, delta) / d delta at delta = 0.
  bool PlusJacobian(const double* x, double* jacobian) const override;
  // y_minus_x = Log(y * x^-1), so Plus(x, Minus(y, x)) == y.
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  // 6x7 row-major d Minus(y, x) / d y at y = x.
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace sgslam::optim
