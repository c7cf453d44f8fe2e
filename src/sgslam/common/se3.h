// The small Lie-group toolkit the project needs (Sophus is not packaged here):
// SO(3) exp/log on quaternions and a rigid transform SE3 with exp/log.
// Tangent order follows Sophus: xi = [rho (translation part); phi (rotation)].
// Name every transform by its frames: T_w_c maps camera coordinates into world.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace sgslam {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Skew-symmetric matrix: Hat(a) * b == a.cross(b).
Eigen::Matrix3d Hat(const Eigen::Vector3d& a);

namespace so3 {
Eigen::Quaterniond Exp(const Eigen::Vector3d& phi);
Eigen::Vector3d Log(const Eigen::Quaterniond& q);  // angle in [0, pi]
// Left Jacobian V(phi) of SO(3), which maps rho to the SE(3) translation.
Eigen::Matrix3d LeftJacobian(const Eigen::Vector3d& phi);
Eigen::Matrix3d LeftJacobianInverse(const Eigen::Vector3d& phi);
}  // namespace so3

class SE3 {
 public:
  SE3() = default;
  SE3(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) : q_(q.normalized()), t_(t) {}
  SE3(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) : q_(Eigen::Quaterniond(R).normalized()), t_(t) {}
  // q must be a unit quaternion already (one read back from a file): kept bit for
  // bit, where normalising it again could change its last bits.
  static SE3 FromUnitQuaternion(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
    SE3 T;
    T.q_ = q;
    T.t_ = t;
    return T;
  }

  static SE3 Exp(const Vector6d& xi);
  Vector6d Log() const;

  SE3 Inverse() const {
    const Eigen::Quaterniond qi = q_.conjugate();
    return SE3(qi, -(qi * t_));
  }
  SE3 operator*(const SE3& o) const { return SE3(q_ * o.q_, q_ * o.t_ + t_); }
  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const { return q_ * p + t_; }

  const Eigen::Quaterniond& quaternion() const { return q_; }
  Eigen::Matrix3d rotation() const { return q_.toRotationMatrix(); }
  const Eigen::Vector3d& translation() const { return t_; }
  Eigen::Matrix4d matrix() const;

 private:
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d t_ = Eigen::Vector3d::Zero();
};

}  // namespace sgslam
