#include "sgslam/optim/rolling_shutter_pose.h"

#include <ceres/cost_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "sgslam/optim/cost_functions.h"
#include "sgslam/optim/se3_manifold.h"

namespace sgslam::optim {
namespace {

using Vector9d = Eigen::Matrix<double, 9, 1>;
using Matrix9d = Eigen::Matrix<double, 9, 9>;

struct Item {
  ReprojectionMeasurement m;
  Eigen::Vector3d p_w;
  double row_time;
  double huber_delta;
};

// All observations and the prior in one block of 10 rows, as PoseOnlyBatchCost
// does for the pose alone (cost_functions.h): per observation the residual r_i
// and its 9-column tangent Jacobian (pose [rho; phi], then delta) are summed
// into c = sum rho(s_i), H = sum w_i J_i^T J_i, g = sum w_i J_i^T r_i; with
// H = R^T R the block returns [R^-T g; sqrt(c - |R^-T g|^2)] and [R; 0].
//
// The keypoint was moved to the middle-row camera with the velocity it was
// corrected with; with the true one it should have been turned by
// Exp(delta row_time) more, so the prediction is p = Exp(-delta row_time) p_c.
// Jacobians to first order in delta * row_time (a few mrad).
class RollingShutterBatchCost final : public ceres::CostFunction {
 public:
  RollingShutterBatchCost(const Intrinsics& K, std::vector<Item> items, double prior_sigma)
      : K_(K), items_(std::move(items)), inv_sigma2_(1.0 / (prior_sigma * prior_sigma)) {
    set_num_residuals(10);
    mutable_parameter_block_sizes()->push_back(kPoseAmbientSize);
    mutable_parameter_block_sizes()->push_back(3);
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
    const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4);
    const Eigen::Map<const Eigen::Vector3d> delta(parameters[1]);
    const bool want_J = jacobians != nullptr && (jacobians[0] != nullptr || jacobians[1] != nullptr);
    double c = delta.squaredNorm() * inv_sigma2_;
    Matrix9d H = Matrix9d::Zero();
    Vector9d g = Vector9d::Zero();
    H.bottomRightCorner<3, 3>().diagonal().setConstant(inv_sigma2_);
    g.tail<3>() = inv_sigma2_ * delta;
    for (const Item& item : items_) {
      const bool ok = item.m.u_right >= 0 ? Accumulate<3>(item, q, t, delta, want_J, c, H, g)
                                          : Accumulate<2>(item, q, t, delta, want_J, c, H, g);
      if (!ok) return false;
    }
    if (!want_J) {
      Eigen::Map<Eigen::Matrix<double, 10, 1>> out(residuals);
      out.setZero();
      out[0] = std::sqrt(c);
      return true;
    }
    Matrix9d R;
    if (!BatchRows<9>(H, g, c, residuals, R)) return false;
    if (jacobians[0] != nullptr) {
      Eigen::Matrix<double, 6, 7, Eigen::RowMajor> M;
      SE3LeftManifold().MinusJacobian(parameters[0], M.data());
      Eigen::Map<Eigen::Matrix<double, 10, 7, Eigen::RowMajor>> J(jacobians[0]);
      J.topRows<9>() = R.leftCols<6>() * M;
      J.row(9).setZero();
    }
    if (jacobians[1] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 10, 3, Eigen::RowMajor>> J(jacobians[1]);
      J.topRows<9>() = R.rightCols<3>();
      J.row(9).setZero();
    }
    return true;
  }

 private:
  template <int N>
  bool Accumulate(const Item& item, const Eigen::Quaterniond& q, const Eigen::Vector3d& t,
                  const Eigen::Vector3d& delta, bool want_J, double& c, Matrix9d& H, Vector9d& g) const {
    const Eigen::Quaterniond turn = so3::Exp(-item.row_time * delta);
    const Eigen::Vector3d p_c = q * item.p_w + t;
    const Eigen::Vector3d p = turn * p_c;
    Eigen::Matrix<double, N, 1> r;
    Eigen::Matrix<double, N, 3> J_p;
    if (!ProjectionResidual<N>(K_, item.m, p, r.data(), want_J ? &J_p : nullptr)) return false;
    double rho = 0, w = 1;
    HuberCost(r.squaredNorm(), item.huber_delta, rho, w);
    c += rho;
    if (!want_J) return true;
    Eigen::Matrix<double, N, 9> J;
    const Eigen::Matrix<double, N, 3> J_pc = J_p * turn.toRotationMatrix();
    J.template leftCols<3>() = J_pc;                      // Exp([rho; phi]) T moves p_c by rho
    J.template middleCols<3>(3) = -J_pc * Hat(p_c);       // ... and by phi x p_c
    J.template rightCols<3>() = item.row_time * J_p * Hat(p);  // delta + e moves p by row_time p x e
    H.noalias() += w * (J.transpose() * J);
    g.noalias() += w * (J.transpose() * r);
    return true;
  }

  Intrinsics K_;
  std::vector<Item> items_;
  double inv_sigma2_;
};

}  // namespace

RollingShutterPoseResult OptimizePoseAndAngularVelocity(const SE3& T_c_w_initial,
                                                        const std::vector<PoseObservation>& obs,
                                                        const std::vector<double>& row_time, const Intrinsics& K,
                                                        const RollingShutterPoseOptions& options) {
  if (row_time.size() != obs.size()) {
    throw std::invalid_argument("OptimizePoseAndAngularVelocity: one row time per observation");
  }
  RollingShutterPoseResult result;
  result.T_c_w = T_c_w_initial;
  // 9 unknowns; with a few matches the rows cannot pin a velocity.
  if (obs.size() < 20 || !(options.prior_sigma > 0)) return result;

  std::vector<Item> items;
  items.reserve(obs.size());
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const ReprojectionMeasurement m{obs[i].uv, obs[i].u_right, std::sqrt(std::max(obs[i].inv_sigma2, 0.0))};
    items.push_back({m, obs[i].p_w, row_time[i], std::sqrt(m.u_right < 0 ? options.chi2_mono : options.chi2_stereo)});
  }
  double pose[kPoseAmbientSize];
  PoseToParams(T_c_w_initial, pose);
  double delta[3] = {0, 0, 0};
  RollingShutterBatchCost cost(K, std::move(items), options.prior_sigma);
  SE3LeftManifold manifold;
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  problem.AddParameterBlock(pose, kPoseAmbientSize, &manifold);
  problem.AddParameterBlock(delta, 3);
  problem.AddResidualBlock(&cost, nullptr, pose, delta);

  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  o.max_num_iterations = options.iterations;
  o.num_threads = 1;
  o.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(o, &problem, &summary);
  if (!summary.IsSolutionUsable() || !std::isfinite(summary.final_cost)) return result;
  result.T_c_w = ParamsToPose(pose);
  result.delta = Eigen::Vector3d(delta[0], delta[1], delta[2]);
  result.ok = true;
  return result;
}

}  // namespace sgslam::optim
