#include "sgslam/optim/pose_graph.h"

#include <ceres/problem.h>
#include <ceres/solver.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include "sgslam/optim/se3_manifold.h"

namespace sgslam::optim {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using PoseParams = std::array<double, kPoseAmbientSize>;

// Adjoint of T for xi = [rho; phi]: T Exp(xi) T^-1 = Exp(Ad(T) xi).
Matrix6d Adjoint(const SE3& T) {
  const Eigen::Matrix3d R = T.rotation();
  Matrix6d A = Matrix6d::Zero();
  A.topLeftCorner<3, 3>() = R;
  A.topRightCorner<3, 3>() = Hat(T.translation()) * R;
  A.bottomRightCorner<3, 3>() = R;
  return A;
}

// Q(rho, phi), the off-diagonal block of SE(3)'s left Jacobian (Barfoot, State
// Estimation for Robotics, eq. 7.86); Taylor coefficients below 0.01 rad, where
// the closed forms cancel.
Eigen::Matrix3d LeftJacobianQ(const Eigen::Vector3d& rho, const Eigen::Vector3d& phi) {
  const double t = phi.norm(), t2 = t * t;
  double c1 = 1.0 / 6 - t2 / 120, c2 = 1.0 / 24 - t2 / 720, c3 = 1.0 / 120 - t2 / 2520;
  if (t >= 1e-2) {
    const double s = std::sin(t), c = std::cos(t);
    c1 = (t - s) / (t2 * t);
    c2 = (t2 + 2 * c - 2) / (2 * t2 * t2);
    c3 = (2 * t - 3 * s + t * c) / (2 * t2 * t2 * t);
  }
  const Eigen::Matrix3d P = Hat(phi), R = Hat(rho);
  const Eigen::Matrix3d PR = P * R, RP = R * P, PRP = PR * P;
  return 0.5 * R + c1 * (PR + RP + PRP) + c2 * (P * PR + RP * P - 3 * PRP) + c3 * (PRP * P + P * PRP);
}

// Inverse left Jacobian of SE(3): Log(Exp(d) Exp(xi)) = xi + J^-1(xi) d + O(d^2).
Matrix6d LeftJacobianInverse(const Vector6d& xi) {
  const Eigen::Matrix3d J_inv = so3::LeftJacobianInverse(xi.tail<3>());
  Matrix6d out = Matrix6d::Zero();
  out.topLeftCorner<3, 3>() = J_inv;
  out.topRightCorner<3, 3>() = -J_inv * LeftJacobianQ(xi.head<3>(), xi.tail<3>()) * J_inv;
  out.bottomRightCorner<3, 3>() = J_inv;
  return out;
}

// Sparse Cholesky, Eigen's first: CHOLMOD is barely faster on a pose graph this
// size and starts OpenMP threads of its own, so the call would not be one thread
// (and is slower on a loaded machine).
ceres::Solver::Options MakeSolverOptions(int iterations) {
  ceres::Solver::Options o;
  o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  o.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;  // if this Ceres has no sparse library
  for (const auto lib : {ceres::EIGEN_SPARSE, ceres::SUITE_SPARSE, ceres::CX_SPARSE}) {
    if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(lib)) {
      o.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
      o.sparse_linear_algebra_library_type = lib;
      break;
    }
  }
  o.max_num_iterations = iterations;
  o.num_threads = 1;
  o.minimizer_progress_to_stdout = false;
  o.logging_type = ceres::SILENT;
  return o;
}

// The problem's blocks: one per node that has a valid edge, in edge order.
// Returns whether any of them is free.
bool AddEdges(const PoseGraphProblem& in, const PoseGraphOptions& options, const std::vector<bool>& fixed,
              std::vector<PoseParams>& poses, ceres::Manifold* manifold, ceres::Problem& problem, int& invalid_edges) {
  std::unordered_map<std::uint64_t, std::size_t> index;
  for (std::size_t k = 0; k < in.nodes.size(); ++k) index.emplace(in.nodes[k].id, k);
  const double s_rho = std::sqrt(options.translation_weight);
  bool any_free = false;
  for (const PoseGraphEdge& e : in.edges) {
    const auto i = index.find(e.id_i), j = index.find(e.id_j);
    if (i == index.end() || j == index.end() || i->second == j->second) {
      ++invalid_edges;
      continue;
    }
    for (const std::size_t k : {i->second, j->second}) {
      if (problem.HasParameterBlock(poses[k].data())) continue;
      problem.AddParameterBlock(poses[k].data(), kPoseAmbientSize, manifold);
      if (fixed[k]) problem.SetParameterBlockConstant(poses[k].data());
      any_free = any_free || !fixed[k];
    }
    const double s = std::sqrt(e.weight);
    const Vector6d sqrt_info = (Vector6d() << s * s_rho, s * s_rho, s * s_rho, s, s, s).finished();
    problem.AddResidualBlock(new RelativePoseCost(e.T_i_j, sqrt_info), nullptr, poses[i->second].data(),
                             poses[j->second].data());
  }
  return any_free;
}

}  // namespace

bool RelativePoseCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const SE3 T_i_j = ParamsToPose(parameters[0]) * ParamsToPose(parameters[1]).Inverse();
  const Vector6d r = (T_j_i_meas_ * T_i_j).Log();
  Eigen::Map<Vector6d> out(residuals);
  out = sqrt_info_.cwiseProduct(r);
  if (jacobians == nullptr) return true;
  // r(Exp(d_i) T_i, Exp(d_j) T_j) = Log(Exp(Ad(T_meas^-1) (d_i - Ad(T_i_j) d_j)) E),
  // E = T_meas^-1 T_i_j, so d r = J^-1(r) Ad(T_meas^-1) (d_i - Ad(T_i_j) d_j).
  const Matrix6d J_i = sqrt_info_.asDiagonal() * LeftJacobianInverse(r) * Adjoint(T_j_i_meas_);
  const SE3LeftManifold manifold;
  for (int k = 0; k < 2; ++k) {
    if (jacobians[k] == nullptr) continue;
    // Ceres multiplies by PlusJacobian P; MinusJacobian M has M P = I.
    Eigen::Matrix<double, 6, 7, Eigen::RowMajor> M;
    manifold.MinusJacobian(parameters[k], M.data());
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobians[k]);
    J = (k == 0 ? J_i : Matrix6d(-J_i * Adjoint(T_i_j))) * M;
  }
  return true;
}

PoseGraphResult OptimizePoseGraph(const PoseGraphProblem& in, const PoseGraphOptions& options) {
  const std::size_t n = in.nodes.size();
  std::vector<PoseParams> poses(n);
  std::vector<bool> fixed(n, false);
  for (std::size_t k = 0; k < n; ++k) {
    PoseToParams(in.nodes[k].T_c_w, poses[k].data());
    fixed[k] = in.nodes[k].fixed;
  }
  // Gauge freedom: without a fixed node, hold the oldest (smallest id).
  if (n > 0 && std::none_of(fixed.begin(), fixed.end(), [](bool f) { return f; })) {
    const auto oldest = std::min_element(in.nodes.begin(), in.nodes.end(),
                                         [](const PoseGraphNode& a, const PoseGraphNode& b) { return a.id < b.id; });
    fixed[oldest - in.nodes.begin()] = true;
  }

  PoseGraphResult result;
  SE3LeftManifold manifold;
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  if (AddEdges(in, options, fixed, poses, &manifold, problem, result.invalid_edges) && options.iterations > 0) {
    ceres::Solver::Summary summary;
    ceres::Solve(MakeSolverOptions(options.iterations), &problem, &summary);
    result.success = summary.IsSolutionUsable();
    result.iterations = std::max(0, static_cast<int>(summary.iterations.size()) - 1);  // entry 0 is the start
    result.initial_cost = summary.initial_cost;
    result.final_cost = result.success ? summary.final_cost : summary.initial_cost;
  }
  result.T_c_w.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const bool moved = result.success && !fixed[k] && problem.HasParameterBlock(poses[k].data());
    result.T_c_w.push_back(moved ? ParamsToPose(poses[k].data()) : in.nodes[k].T_c_w);
  }
  return result;
}

}  // namespace sgslam::optim
