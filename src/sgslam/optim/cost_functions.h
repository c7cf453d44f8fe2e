// Reprojection residuals of ORB-SLAM2's optimiser (Optimizer.cc edges
// EdgeSE3ProjectXYZ[OnlyPose] and EdgeStereoSE3ProjectXYZ[OnlyPose]) as Ceres
// cost functions with analytic Jacobians.
//
// p_c = T_c_w * p_w, u = fx x/z + cx, v = fy y/z + cy, and for RGB-D "stereo"
// observations the virtual right coordinate u_r = u - bf/z (bf = baseline*fx).
// Residual r = sqrt(inv_sigma2) * (projection - measurement), so |r|^2 is the
// chi2 that ORB-SLAM2 tests against 5.991 (2 dof) or 7.815 (3 dof).
// Pose blocks use the 7-double layout of se3_manifold.h; Jacobians are with
// respect to that ambient layout. Evaluate returns false for points at depth
// <= kMinDepth so the trust region rejects steps that move a point behind a camera.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

namespace sgslam::optim {

struct Intrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double bf = 0;  // baseline * fx [px * m]; u_right = u - bf / z
};

inline constexpr double kMinDepth = 1e-6;  // [m]

// One measurement: pixel, virtual right coordinate (< 0: monocular), weight.
struct ReprojectionMeasurement {
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  double u_right = -1;
  double sqrt_info = 1;  // sqrt(inv_sigma2) of the keypoint's pyramid level
};

// Residual (N = 2 mono, 3 stereo) of a camera-frame point and, when J is given,
// its Jacobian d r / d p_c. Returns false behind the camera.
template <int N>
bool ProjectionResidual(const Intrinsics& K, const ReprojectionMeasurement& m, const Eigen::Vector3d& p_c,
                        double* residual, Eigen::Matrix<double, N, 3>* J);

// Squared weighted error (chi2) of a measurement, +infinity behind the camera.
double ReprojectionChi2(const Intrinsics& K, const ReprojectionMeasurement& m, const Eigen::Vector3d& p_c);

// Pose-only: fixed world point, parameter block = pose (7).
template <int N>
class PoseOnlyReprojectionCost final : public ceres::SizedCostFunction<N, 7> {
 public:
  PoseOnlyReprojectionCost(const Intrinsics& K, const ReprojectionMeasurement& m, const Eigen::Vector3d& p_w)
      : K_(K), m_(m), p_w_(p_w) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Intrinsics K_;
  ReprojectionMeasurement m_;
  Eigen::Vector3d p_w_;
};

// Bundle adjustment: parameter blocks = pose (7), world point (3).
template <int N>
class BaReprojectionCost final : public ceres::SizedCostFunction<N, 7, 3> {
 public:
  BaReprojectionCost(const Intrinsics& K, const ReprojectionMeasurement& m) : K_(K), m_(m) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Intrinsics K_;
  ReprojectionMeasurement m_;
};

// Huber's cost rho(s) of a squared residual s and its derivative w = rho'(s),
// as ceres::HuberLoss(delta); delta <= 0: plain least squares (s and 1).
inline void HuberCost(double s, double delta, double& rho, double& w) {
  rho = s;
  w = 1;
  if (delta > 0 && s > delta * delta) {  // beyond delta: rho = 2 delta sqrt(s) - delta^2
    const double root = std::sqrt(s);
    rho = 2 * delta * root - delta * delta;
    w = delta / root;
  }
}

// The D + 1 rows a batched block hands Ceres for a problem with cost c, Gauss-
// Newton matrix H and gradient g over D tangent parameters (PoseOnlyBatchCost
// below): with H = R^T R, r' = [R^-T g; sqrt(c - |R^-T g|^2)] and J' = [R; 0].
// False when H is not positive definite.
template <int D>
bool BatchRows(const Eigen::Matrix<double, D, D>& H, const Eigen::Matrix<double, D, 1>& g, double c,
               double* residuals, Eigen::Matrix<double, D, D>& R) {
  const Eigen::LLT<Eigen::Matrix<double, D, D>> llt(H);
  if (llt.info() != Eigen::Success) return false;
  R = llt.matrixU();
  const Eigen::Matrix<double, D, 1> z = R.transpose().template triangularView<Eigen::Lower>().solve(g);
  Eigen::Map<Eigen::Matrix<double, D + 1, 1>> out(residuals);
  out.template head<D>() = z;
  out[D] = std::sqrt(std::max(c - z.squaredNorm(), 0.0));
  return true;
}

// Pose-only, every observation in one residual block of 7 rows. Ceres spends
// most of a pose optimisation on bookkeeping proportional to the Jacobian's
// size, so the block hands Ceres an equivalent 7-row problem.
// Per observation i (residual r_i, tangent Jacobian J_i, s_i = |r_i|^2) it sums
// c = sum rho(s_i), H = sum w_i J_i^T J_i and g = sum w_i J_i^T r_i with
// w_i = rho'(s_i): exactly what Ceres makes of one block and one HuberLoss per
// observation (its correction for rho'' <= 0, as Huber's is). With H = R^T R
// (Cholesky) it returns r' = [R^-T g; sqrt(c - |R^-T g|^2)] and J' = [R; 0]:
// |r'|^2 = c, J'^T J' = H, J'^T r' = g, so every Levenberg-Marquardt step,
// cost and tolerance test is that problem's. c >= |R^-T g|^2 holds because
// rho(s) >= rho'(s) s for Huber. (Without Jacobians it returns [sqrt(c), 0...].)
// Evaluation fails for a point behind the camera, or when H is not positive
// definite (degenerate geometry).
class PoseOnlyBatchCost final : public ceres::CostFunction {
 public:
  struct Item {
    ReprojectionMeasurement m;
    Eigen::Vector3d p_w;
    double huber_delta = 0;  // sqrt of the chi2 threshold; <= 0: plain least squares
  };
  PoseOnlyBatchCost(const Intrinsics& K, std::vector<Item> items);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  // The full problem the 7 rows stand for (tests): the stacked residuals (3 or
  // 2 rows per item) and, when J is given, their tangent Jacobian (rows x 6,
  // left perturbation [rho; phi]), both times sqrt(w_i) as Ceres corrects
  // them; cost (if given) = sum rho(s_i). False behind the camera.
  bool EvaluateFull(const double* pose, Eigen::VectorXd& r, Eigen::MatrixXd* J, double* cost = nullptr) const;

 private:
  Intrinsics K_;
  std::vector<Item> items_;
  int rows_ = 0;
};

using PoseOnlyMonoCost = PoseOnlyReprojectionCost<2>;
using PoseOnlyStereoCost = PoseOnlyReprojectionCost<3>;
using BaMonoCost = BaReprojectionCost<2>;
using BaStereoCost = BaReprojectionCost<3>;

// Creates the mono or stereo variant as the measurement asks (caller owns).
ceres::CostFunction* MakePoseOnlyCost(const Intrinsics& K, const ReprojectionMeasurement& m,
                                      const Eigen::Vector3d& p_w);
ceres::CostFunction* MakeBaCost(const Intrinsics& K, const ReprojectionMeasurement& m);

}  // namespace sgslam::optim
