#include "sgslam/optim/local_ba.h"

#include <ceres/iteration_callback.h>
#include <ceres/loss_function.h>
#include <ceres/ordered_groups.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "sgslam/optim/se3_manifold.h"

namespace sgslam::optim {
namespace {

using PoseParams = std::array<double, kPoseAmbientSize>;

// Up to this many free keyframes the reduced camera system (6n x 6n) is
// factorised densely: no symbolic analysis, and faster than a sparse solver at
// local-BA sizes. Larger problems use a sparse Schur complement with whatever
// sparse backend this Ceres build has.
constexpr int kDenseSchurMaxFreeKeyframes = 60;

void ChooseLinearSolver(int free_keyframes, ceres::Solver::Options& o) {
  o.linear_solver_type = ceres::DENSE_SCHUR;
  if (free_keyframes <= kDenseSchurMaxFreeKeyframes) return;
  for (const auto lib : {ceres::SUITE_SPARSE, ceres::EIGEN_SPARSE, ceres::CX_SPARSE}) {
    if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(lib)) {
      o.linear_solver_type = ceres::SPARSE_SCHUR;
      o.sparse_linear_algebra_library_type = lib;
      return;
    }
  }
  o.linear_solver_type = ceres::ITERATIVE_SCHUR;  // matrix-free, no sparse library needed
  o.preconditioner_type = ceres::SCHUR_JACOBI;
}

// Polled after every LM iteration. Terminating "successfully" keeps the last
// accepted iterate (SOLVER_ABORT would make Ceres discard all progress).
class AbortCallback final : public ceres::IterationCallback {
 public:
  explicit AbortCallback(const std::function<bool()>& should_abort) : should_abort_(should_abort) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    if (!should_abort_ || !should_abort_()) return ceres::SOLVER_CONTINUE;
    aborted = true;
    return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
  }
  bool aborted = false;

 private:
  const std::function<bool()>& should_abort_;
};

struct BaState {
  const BaProblem& in;
  std::vector<PoseParams> poses;
  std::vector<Eigen::Vector3d> points;
  std::vector<ReprojectionMeasurement> meas;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;  // null: invalid indices
  std::vector<bool> fixed;

  double Chi2(std::size_t i) const {
    const BaObservation& o = in.observations[i];
    return ReprojectionChi2(in.intrinsics, meas[i], ParamsToPose(poses[o.keyframe].data()) * points[o.point]);
  }
  // ORB-SLAM2's outlier test: chi2 above the threshold or the point behind the camera.
  bool IsOutlier(std::size_t i, const BaOptions& opt) const {
    if (!costs[i]) return true;
    return !(Chi2(i) <= (meas[i].u_right < 0 ? opt.chi2_mono : opt.chi2_stereo));
  }
};

// A point seen by a single monocular observation is free along its ray: LM
// would let it drift there (and it tells the cameras nothing), so such an
// observation sits the stage out and the point keeps its position.
std::vector<bool> Constrained(const BaState& s, const std::vector<bool>& active) {
  std::vector<int> dims(s.points.size(), 0);
  for (std::size_t i = 0; i < active.size(); ++i)
    if (active[i]) dims[s.in.observations[i].point] += s.meas[i].u_right < 0 ? 2 : 3;
  std::vector<bool> use(active.size(), false);
  for (std::size_t i = 0; i < active.size(); ++i) use[i] = active[i] && dims[s.in.observations[i].point] >= 3;
  return use;
}

// One LM stage over the active observations; returns false when nothing ran.
bool RunStage(BaState& s, const std::vector<bool>& active_in, bool robust, int iterations, const BaOptions& opt,
              AbortCallback& callback, ceres::Solver::Summary& summary) {
  const std::vector<bool> active = Constrained(s, active_in);
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  SE3LeftManifold manifold;
  ceres::HuberLoss huber_mono(std::sqrt(opt.chi2_mono)), huber_stereo(std::sqrt(opt.chi2_stereo));
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  std::vector<bool> pose_added(s.poses.size(), false);
  int free_keyframes = 0;
  for (std::size_t i = 0; i < active.size(); ++i) {
    if (!active[i]) continue;
    const BaObservation& o = s.in.observations[i];
    double* pose = s.poses[o.keyframe].data();
    double* point = s.points[o.point].data();
    if (!pose_added[o.keyframe]) {
      pose_added[o.keyframe] = true;
      problem.AddParameterBlock(pose, kPoseAmbientSize, &manifold);
      if (s.fixed[o.keyframe]) problem.SetParameterBlockConstant(pose);
      free_keyframes += s.fixed[o.keyframe] ? 0 : 1;
      ordering->AddElementToGroup(pose, 1);
    }
    if (!ordering->IsMember(point)) ordering->AddElementToGroup(point, 0);  // Schur: points first
    ceres::LossFunction* loss = nullptr;
    if (robust) loss = s.meas[i].u_right < 0 ? &huber_mono : &huber_stereo;
    problem.AddResidualBlock(s.costs[i].get(), loss, pose, point);
  }
  if (problem.NumResidualBlocks() == 0 || iterations <= 0) return false;

  ceres::Solver::Options so;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  ChooseLinearSolver(free_keyframes, so);
  so.linear_solver_ordering = ordering;
  so.max_num_iterations = iterations;
  so.num_threads = std::max(1, opt.threads);
  so.minimizer_progress_to_stdout = false;
  so.logging_type = ceres::SILENT;
  so.callbacks.push_back(&callback);
  ceres::Solve(so, &problem, &summary);
  return true;
}

}  // namespace

BaResult SolveLocalBa(const BaProblem& in, const BaOptions& options, const std::function<bool()>& should_abort) {
  const std::size_t n_kf = in.keyframes.size(), n_pt = in.points.size(), n_obs = in.observations.size();
  BaState s{in,
            std::vector<PoseParams>(n_kf),
            std::vector<Eigen::Vector3d>(n_pt),
            std::vector<ReprojectionMeasurement>(n_obs),
            std::vector<std::unique_ptr<ceres::CostFunction>>(n_obs),
            std::vector<bool>(n_kf, false)};
  for (std::size_t k = 0; k < n_kf; ++k) {
    PoseToParams(in.keyframes[k].T_c_w, s.poses[k].data());
    s.fixed[k] = in.keyframes[k].fixed;
  }
  for (std::size_t p = 0; p < n_pt; ++p) s.points[p] = in.points[p].p_w;
  // Gauge freedom: without a fixed keyframe, hold the oldest (smallest id).
  if (n_kf > 0 && std::none_of(s.fixed.begin(), s.fixed.end(), [](bool f) { return f; })) {
    const auto oldest = std::min_element(in.keyframes.begin(), in.keyframes.end(),
                                         [](const BaKeyFrame& a, const BaKeyFrame& b) { return a.id < b.id; });
    s.fixed[oldest - in.keyframes.begin()] = true;
  }

  std::vector<bool> active(n_obs, false);
  for (std::size_t i = 0; i < n_obs; ++i) {
    const BaObservation& o = in.observations[i];
    if (o.keyframe < 0 || o.point < 0 || static_cast<std::size_t>(o.keyframe) >= n_kf ||
        static_cast<std::size_t>(o.point) >= n_pt)
      continue;
    s.meas[i] = {o.uv, o.u_right, std::sqrt(std::max(o.inv_sigma2, 0.0))};
    s.costs[i].reset(MakeBaCost(in.intrinsics, s.meas[i]));
    // A point behind the camera would fail Ceres' initial evaluation.
    active[i] = std::isfinite(s.Chi2(i));
  }

  BaResult result;
  AbortCallback callback(should_abort);
  ceres::Solver::Summary first;
  if (RunStage(s, active, /*robust=*/true, options.first_iterations, options, callback, first)) {
    result.initial_cost = first.initial_cost;
    result.final_cost = first.final_cost;
    result.iterations = static_cast<int>(first.iterations.size()) - 1;  // entry 0 is the start
  }
  if (!callback.aborted) {
    for (std::size_t i = 0; i < n_obs; ++i) active[i] = active[i] && !s.IsOutlier(i, options);
    ceres::Solver::Summary second;
    if (RunStage(s, active, /*robust=*/false, options.second_iterations, options, callback, second)) {
      result.final_cost = second.final_cost;
      result.iterations += static_cast<int>(second.iterations.size()) - 1;
    }
  }
  result.aborted = callback.aborted;

  result.T_c_w.reserve(n_kf);
  for (const PoseParams& x : s.poses) result.T_c_w.push_back(ParamsToPose(x.data()));
  result.p_w = s.points;
  result.outlier.resize(n_obs);
  for (std::size_t i = 0; i < n_obs; ++i) result.outlier[i] = s.IsOutlier(i, options);
  return result;
}

}  // namespace sgslam::optim
