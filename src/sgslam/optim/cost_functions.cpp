#include "sgslam/optim/cost_functions.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "sgslam/common/se3.h"
#include "sgslam/optim/se3_manifold.h"

namespace sgslam::optim {
namespace {

using Matrix34 = Eigen::Matrix<double, 3, 4>;

// d (q * p) / d [qx qy qz qw] for the formula Eigen evaluates,
// q * p = p + 2 w (v x p) + 2 v x (v x p):
// d/dv = -2 w [p]x + 2 ((v.p) I + v p^T - 2 p v^T), d/dw = 2 v x p.
Matrix34 RotatePointJacobian(const Eigen::Quaterniond& q, const Eigen::Vector3d& p) {
  const Eigen::Vector3d v = q.vec();
  const double w = q.w();
  Matrix34 J;
  J.leftCols<3>() =
      -2.0 * w * Hat(p) + 2.0 * (v.dot(p) * Eigen::Matrix3d::Identity() + v * p.transpose() - 2.0 * p * v.transpose());
  J.col(3) = 2.0 * v.cross(p);
  return J;
}

// Fills the row-major N x 7 pose Jacobian from d r / d p_c; p_c = q * p_w + t.
template <int N>
void PoseJacobian(const Eigen::Matrix<double, N, 3>& J_pc, const Eigen::Quaterniond& q, const Eigen::Vector3d& p_w,
                  double* out) {
  Eigen::Map<Eigen::Matrix<double, N, 7, Eigen::RowMajor>> J(out);
  J.template leftCols<4>() = J_pc * RotatePointJacobian(q, p_w);
  J.template rightCols<3>() = J_pc;
}

}  // namespace

template <int N>
bool ProjectionResidual(const Intrinsics& K, const ReprojectionMeasurement& m, const Eigen::Vector3d& p_c,
                        double* residual, Eigen::Matrix<double, N, 3>* J) {
  const double z = p_c.z();
  if (!(z > kMinDepth)) return false;
  const double iz = 1.0 / z;
  const double x = p_c.x() * iz, y = p_c.y() * iz;
  const double u = K.fx * x + K.cx;
  const double w = m.sqrt_info;
  residual[0] = w * (u - m.uv.x());
  residual[1] = w * (K.fy * y + K.cy - m.uv.y());
  if constexpr (N == 3) residual[2] = w * (u - K.bf * iz - m.u_right);
  if (J != nullptr) {
    // d(u, v, u_r) / d(X, Y, Z), the rows of ORB-SLAM2's linearizeOplus.
    (*J)(0, 0) = w * K.fx * iz;
    (*J)(0, 1) = 0;
    (*J)(0, 2) = -w * K.fx * x * iz;
    (*J)(1, 0) = 0;
    (*J)(1, 1) = w * K.fy * iz;
    (*J)(1, 2) = -w * K.fy * y * iz;
    if constexpr (N == 3) {
      (*J)(2, 0) = (*J)(0, 0);
      (*J)(2, 1) = 0;
      (*J)(2, 2) = (*J)(0, 2) + w * K.bf * iz * iz;
    }
  }
  return true;
}

double ReprojectionChi2(const Intrinsics& K, const ReprojectionMeasurement& m, const Eigen::Vector3d& p_c) {
  double r[3];
  if (m.u_right < 0) {
    if (!ProjectionResidual<2>(K, m, p_c, r, nullptr)) return std::numeric_limits<double>::infinity();
    return r[0] * r[0] + r[1] * r[1];
  }
  if (!ProjectionResidual<3>(K, m, p_c, r, nullptr)) return std::numeric_limits<double>::infinity();
  return r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
}

template <int N>
bool PoseOnlyReprojectionCost<N>::Evaluate(double const* const* parameters, double* residuals,
                                           double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4);
  const Eigen::Vector3d p_c = q * p_w_ + t;
  const bool want_J = jacobians != nullptr && jacobians[0] != nullptr;
  Eigen::Matrix<double, N, 3> J_pc;
  if (!ProjectionResidual<N>(K_, m_, p_c, residuals, want_J ? &J_pc : nullptr)) return false;
  if (want_J) PoseJacobian<N>(J_pc, q, p_w_, jacobians[0]);
  return true;
}

template <int N>
bool BaReprojectionCost<N>::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4);
  const Eigen::Map<const Eigen::Vector3d> p_w(parameters[1]);
  const Eigen::Vector3d p_c = q * p_w + t;
  const bool want_pose = jacobians != nullptr && jacobians[0] != nullptr;
  const bool want_point = jacobians != nullptr && jacobians[1] != nullptr;
  Eigen::Matrix<double, N, 3> J_pc;
  if (!ProjectionResidual<N>(K_, m_, p_c, residuals, want_pose || want_point ? &J_pc : nullptr)) return false;
  if (want_pose) PoseJacobian<N>(J_pc, q, p_w, jacobians[0]);
  if (want_point) {
    // d p_c / d p_w = R(q).
    Eigen::Map<Eigen::Matrix<double, N, 3, Eigen::RowMajor>> J_point(jacobians[1]);
    J_point = J_pc * q.toRotationMatrix();
  }
  return true;
}

namespace {

// One observation of PoseOnlyBatchCost at the pose (q, t): its residual (N
// rows at r, unscaled) and, when J is given, its N x 6 tangent Jacobian; rho
// and w are the Huber cost rho(s) of s = |r|^2 and its derivative rho'(s)
// (s and 1 without a kernel or within delta).
template <int N>
bool PoseRows(const Intrinsics& K, const PoseOnlyBatchCost::Item& item, const Eigen::Quaterniond& q,
              const Eigen::Vector3d& t, double* r, Eigen::Matrix<double, N, 6>* J, double& rho, double& w) {
  const Eigen::Vector3d p_c = q * item.p_w + t;
  Eigen::Matrix<double, N, 3> J_pc;
  if (!ProjectionResidual<N>(K, item.m, p_c, r, J != nullptr ? &J_pc : nullptr)) return false;
  HuberCost(Eigen::Map<const Eigen::Matrix<double, N, 1>>(r).squaredNorm(), item.huber_delta, rho, w);
  if (J != nullptr) {
    // Exp([rho; phi]) * T moves p_c by rho + phi x p_c.
    J->template leftCols<3>() = J_pc;
    J->template rightCols<3>() = -J_pc * Hat(p_c);
  }
  return true;
}

// Adds one observation to c = sum rho, H = sum w J^T J and g = sum w J^T r.
template <int N>
bool AccumulateNormal(const Intrinsics& K, const PoseOnlyBatchCost::Item& item, const Eigen::Quaterniond& q,
                      const Eigen::Vector3d& t, bool want_J, double& c, Eigen::Matrix<double, 6, 6>& H,
                      Eigen::Matrix<double, 6, 1>& g) {
  Eigen::Matrix<double, N, 1> r;
  Eigen::Matrix<double, N, 6> J;
  double rho = 0, w = 1;
  if (!PoseRows<N>(K, item, q, t, r.data(), want_J ? &J : nullptr, rho, w)) return false;
  c += rho;
  if (want_J) {
    H.noalias() += w * (J.transpose() * J);
    g.noalias() += w * (J.transpose() * r);
  }
  return true;
}

}  // namespace

PoseOnlyBatchCost::PoseOnlyBatchCost(const Intrinsics& K, std::vector<Item> items) : K_(K), items_(std::move(items)) {
  for (const Item& i : items_) rows_ += i.m.u_right < 0 ? 2 : 3;
  set_num_residuals(7);
  mutable_parameter_block_sizes()->push_back(7);
}

bool PoseOnlyBatchCost::EvaluateFull(const double* pose, Eigen::VectorXd& r, Eigen::MatrixXd* J,
                                     double* cost) const {
  const Eigen::Map<const Eigen::Quaterniond> q(pose);
  const Eigen::Map<const Eigen::Vector3d> t(pose + 4);
  r.resize(rows_);
  if (J != nullptr) J->resize(rows_, 6);
  double c = 0;
  int row = 0;
  for (const Item& item : items_) {
    const int n = item.m.u_right >= 0 ? 3 : 2;
    double rho = 0, w = 1;
    Eigen::Matrix<double, 3, 6> J3;
    Eigen::Matrix<double, 2, 6> J2;
    const bool ok = n == 3 ? PoseRows<3>(K_, item, q, t, r.data() + row, J != nullptr ? &J3 : nullptr, rho, w)
                           : PoseRows<2>(K_, item, q, t, r.data() + row, J != nullptr ? &J2 : nullptr, rho, w);
    if (!ok) return false;
    // Ceres' correction for a HuberLoss block (rho'' <= 0): rows and Jacobian times sqrt(rho').
    r.segment(row, n) *= std::sqrt(w);
    if (J != nullptr) {
      if (n == 3) J->middleRows<3>(row) = std::sqrt(w) * J3;
      else J->middleRows<2>(row) = std::sqrt(w) * J2;
    }
    c += rho;
    row += n;
  }
  if (cost != nullptr) *cost = c;
  return true;
}

bool PoseOnlyBatchCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4);
  const bool want_J = jacobians != nullptr && jacobians[0] != nullptr;
  // Accumulated in one pass: c = sum rho, and with Jacobians H = sum w J^T J,
  // g = sum w J^T r (the gradient of c / 2 and Ceres' Gauss-Newton matrix).
  double c = 0;
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
  for (const Item& item : items_) {
    const bool ok = item.m.u_right >= 0 ? AccumulateNormal<3>(K_, item, q, t, want_J, c, H, g)
                                        : AccumulateNormal<2>(K_, item, q, t, want_J, c, H, g);
    if (!ok) return false;
  }
  if (!want_J) {
    Eigen::Map<Eigen::Matrix<double, 7, 1>> out(residuals);
    out.setZero();
    out[0] = std::sqrt(c);
    return true;
  }
  Eigen::Matrix<double, 6, 6> R;
  if (!BatchRows<6>(H, g, c, residuals, R)) return false;
  // Ceres wants d r' / d x in the 7 ambient coordinates and multiplies by the
  // manifold's PlusJacobian P; MinusJacobian M has M P = I, so J' M gives J'.
  Eigen::Matrix<double, 6, 7, Eigen::RowMajor> M;
  SE3LeftManifold().MinusJacobian(parameters[0], M.data());
  Eigen::Map<Eigen::Matrix<double, 7, 7, Eigen::RowMajor>> J(jacobians[0]);
  J.topRows<6>() = R * M;
  J.row(6).setZero();
  return true;
}

ceres::CostFunction* MakePoseOnlyCost(const Intrinsics& K, const ReprojectionMeasurement& m,
                                      const Eigen::Vector3d& p_w) {
  if (m.u_right < 0) return new PoseOnlyMonoCost(K, m, p_w);
  return new PoseOnlyStereoCost(K, m, p_w);
}

ceres::CostFunction* MakeBaCost(const Intrinsics& K, const ReprojectionMeasurement& m) {
  if (m.u_right < 0) return new BaMonoCost(K, m);
  return new BaStereoCost(K, m);
}

template bool ProjectionResidual<2>(const Intrinsics&, const ReprojectionMeasurement&, const Eigen::Vector3d&, double*,
                                    Eigen::Matrix<double, 2, 3>*);
template bool ProjectionResidual<3>(const Intrinsics&, const ReprojectionMeasurement&, const Eigen::Vector3d&, double*,
                                    Eigen::Matrix<double, 3, 3>*);
template class PoseOnlyReprojectionCost<2>;
template class PoseOnlyReprojectionCost<3>;
template class BaReprojectionCost<2>;
template class BaReprojectionCost<3>;

}  // namespace sgslam::optim
