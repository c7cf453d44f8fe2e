#include "sgslam/optim/pose_optimizer.h"

#include <ceres/problem.h>
#include <ceres/solver.h>

#include <cmath>
#include <memory>

#include "sgslam/optim/se3_manifold.h"

namespace sgslam::optim {
namespace {

ceres::Solver::Options MakeSolverOptions(int iterations) {
  ceres::Solver::Options o;
  o.minimizer_type = ceres::TRUST_REGION;
  o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  // One block of 7 rows standing for all observations (PoseOnlyBatchCost): a
  // 7x6 dense problem.
  o.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  o.max_num_iterations = iterations;
  o.num_threads = 1;
  o.minimizer_progress_to_stdout = false;
  o.logging_type = ceres::SILENT;
  return o;
}

// Classifies every observation at the current pose (ORB-SLAM2 evaluates the
// excluded edges too, so a point can come back). Returns the inlier count.
int Classify(const SE3& T_c_w, const std::vector<PoseObservation>& obs,
             const std::vector<ReprojectionMeasurement>& meas, const Intrinsics& K, const PoseOptimizerOptions& options,
             std::vector<bool>& inlier) {
  int n = 0;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const double th = meas[i].u_right < 0 ? options.chi2_mono : options.chi2_stereo;
    inlier[i] = ReprojectionChi2(K, meas[i], T_c_w * obs[i].p_w) <= th;
    n += inlier[i] ? 1 : 0;
  }
  return n;
}

}  // namespace

PoseOptimizationResult OptimizePose(const SE3& T_c_w_initial, const std::vector<PoseObservation>& obs,
                                    const Intrinsics& K, const PoseOptimizerOptions& options) {
  const std::size_t n = obs.size();
  PoseOptimizationResult result;
  result.T_c_w = T_c_w_initial;
  result.inlier.assign(n, false);

  std::vector<ReprojectionMeasurement> meas(n);
  int usable = 0;
  for (std::size_t i = 0; i < n; ++i) {
    meas[i] = {obs[i].uv, obs[i].u_right, std::sqrt(std::max(obs[i].inv_sigma2, 0.0))};
    // Start with every observation in front of the camera (ORB-SLAM2 starts
    // with all; one behind would make Ceres reject the initial point).
    result.inlier[i] = (T_c_w_initial * obs[i].p_w).z() > kMinDepth && !obs[i].start_excluded;
    usable += result.inlier[i] && !obs[i].classify_only ? 1 : 0;
  }

  double pose[kPoseAmbientSize];
  PoseToParams(T_c_w_initial, pose);
  SE3LeftManifold manifold;
  const double delta_mono = std::sqrt(options.chi2_mono), delta_stereo = std::sqrt(options.chi2_stereo);
  const ceres::Solver::Options solver_options = MakeSolverOptions(options.iterations);

  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.disable_all_safety_checks = true;  // blocks built here, known valid

  // A 6-dof pose needs at least 3 points (ORB-SLAM2 returns below 3 too).
  for (int round = 0; round < options.rounds && usable >= 3; ++round) {
    // ORB-SLAM2 drops the kernel after classifying in round 2 of 0..3.
    const bool robust = round < options.rounds - 1 || options.rounds == 1;
    std::vector<PoseOnlyBatchCost::Item> items;
    items.reserve(static_cast<std::size_t>(usable));
    for (std::size_t i = 0; i < n; ++i) {
      if (!result.inlier[i] || obs[i].classify_only) continue;
      items.push_back({meas[i], obs[i].p_w, robust ? (meas[i].u_right < 0 ? delta_mono : delta_stereo) : 0.0});
    }
    PoseOnlyBatchCost cost(K, std::move(items));
    ceres::Problem problem(problem_options);
    problem.AddParameterBlock(pose, kPoseAmbientSize, &manifold);
    problem.AddResidualBlock(&cost, nullptr, pose);
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
    if (!summary.IsSolutionUsable()) break;  // pose left at the last good value

    Classify(ParamsToPose(pose), obs, meas, K, options, result.inlier);
    usable = 0;
    for (std::size_t i = 0; i < n; ++i) usable += result.inlier[i] && !obs[i].classify_only ? 1 : 0;
    if (usable < 10) break;
  }
  result.T_c_w = ParamsToPose(pose);
  result.inliers = Classify(result.T_c_w, obs, meas, K, options, result.inlier);
  return result;
}

}  // namespace sgslam::optim
