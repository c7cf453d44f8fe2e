// Bundle adjustment of a set of keyframes: local (ORB-SLAM2's
// LocalBundleAdjustment: the new keyframe and its covisibles are free, the other
// keyframes that see their points are fixed) and global (every keyframe free but
// the first, run once when the sequence ends). The problem is copied out under
// the shared lock, solved without a lock, and written back under the exclusive lock.
#include <map>
#include <mutex>
#include <shared_mutex>

#include "sgslam/common/stats.h"
#include "sgslam/mapping/ba_problem.h"
#include "sgslam/mapping/local_mapper.h"
#include "sgslam/optim/local_ba.h"

namespace sgslam {

namespace {

constexpr int kLocalBaFirstIterations = 5;    // local BA with a robust kernel (ORB-SLAM2)
constexpr int kLocalBaSecondIterations = 10;  // local BA after removing outliers (ORB-SLAM2)
// Free keyframes of local BA: the new one and its best covisibles. The Schur
// complement grows with their square, and in a small scene every keyframe is
// covisible with every other.
constexpr std::size_t kMaxLocalKeyFrames = 25;

}  // namespace

bool LocalMapper::LocalBundleAdjustment(const std::shared_ptr<KeyFrame>& kf,
                                        const std::function<bool()>& interrupted, MappingStats& stats) {
  std::vector<std::shared_ptr<KeyFrame>> free;
  {
    std::shared_lock lock(map_.mutex());
    if (map_.keyframes().size() <= 2) return true;
    free.push_back(kf);
    for (const auto& k : kf->Covisibles(kMaxLocalKeyFrames - 1)) free.push_back(k);
  }
  optim::BaOptions options;
  options.first_iterations = kLocalBaFirstIterations;
  options.second_iterations = kLocalBaSecondIterations;
  return AdjustKeyFrames(free, options, interrupted, stats);
}

MappingStats LocalMapper::GlobalBundleAdjustment() {
  Stopwatch watch;
  MappingStats stats;
  std::vector<std::shared_ptr<KeyFrame>> free;
  {
    std::shared_lock lock(map_.mutex());
    if (map_.keyframes().size() <= 2) return stats;
    for (const auto& [id, k] : map_.keyframes()) {
      if (!k->bad()) free.push_back(k);
    }
  }
  optim::BaOptions options;
  options.first_iterations = config_.final_ba_iterations;
  options.second_iterations = config_.final_ba_iterations;
  stats.ba_done = true;
  AdjustKeyFrames(free, options, {}, stats);
  stats.ba_ms = stats.ms = watch.ElapsedMs();
  return stats;
}

BaSnapshot CopyBaProblem(const std::vector<std::shared_ptr<KeyFrame>>& free) {
  BaSnapshot s;
  if (free.empty()) return s;
  const Camera& cam = *free.front()->features->camera;
  s.problem.intrinsics = {cam.fx(), cam.fy(), cam.cx(), cam.cy(), cam.baseline_fx()};
  std::map<std::uint64_t, int> kf_index;
  const auto add_kf = [&](const std::shared_ptr<KeyFrame>& k, bool fixed) {
    kf_index[k->id] = static_cast<int>(s.keyframes.size());
    s.keyframes.push_back(k);
    s.problem.keyframes.push_back({k->id, k->T_c_w(), fixed || k->id == 0});
  };
  for (const auto& k : free) {
    if (!k->bad() && !kf_index.count(k->id)) add_kf(k, false);
  }
  const std::size_t local_count = s.keyframes.size();
  std::map<std::uint64_t, int> point_index;
  for (std::size_t k = 0; k < local_count; ++k) {
    for (const auto& p : s.keyframes[k]->map_points()) {
      if (!p || p->bad() || point_index.count(p->id)) continue;
      point_index[p->id] = static_cast<int>(s.points.size());
      s.points.push_back(p);
      s.problem.points.push_back({p->id, p->position()});
    }
  }
  for (std::size_t pi = 0; pi < s.points.size(); ++pi) {
    for (const auto& [kf_id, obs] : s.points[pi]->observations()) {
      const auto other = obs.keyframe.lock();
      if (!other || other->bad()) continue;
      if (!kf_index.count(kf_id)) add_kf(other, /*fixed=*/true);
      const Features& f = *other->features;
      optim::BaObservation o;
      o.keyframe = kf_index[kf_id];
      o.point = static_cast<int>(pi);
      o.uv = {f.keys_un[obs.index].pt.x, f.keys_un[obs.index].pt.y};
      o.u_right = f.u_right[obs.index];
      o.inv_sigma2 = f.scale->inv_sigma2[static_cast<std::size_t>(f.keys_un[obs.index].octave)];
      s.problem.observations.push_back(o);
    }
  }
  return s;
}

bool LocalMapper::AdjustKeyFrames(const std::vector<std::shared_ptr<KeyFrame>>& free,
                                  const optim::BaOptions& options, const std::function<bool()>& interrupted,
                                  MappingStats& stats) {
  if (free.empty()) return true;
  BaSnapshot snapshot;
  {
    std::shared_lock lock(map_.mutex());
    snapshot = CopyBaProblem(free);
  }
  const optim::BaProblem& problem = snapshot.problem;
  const auto& keyframes = snapshot.keyframes;
  const auto& points = snapshot.points;
  stats.local_keyframes = static_cast<int>(keyframes.size());
  stats.local_points = static_cast<int>(points.size());
  const optim::BaResult result = optim::SolveLocalBa(problem, options, interrupted);

  std::unique_lock lock(map_.mutex());
  for (std::size_t o = 0; o < problem.observations.size(); ++o) {
    if (!result.outlier[o]) continue;
    const auto& obs = problem.observations[o];
    const auto& k = keyframes[static_cast<std::size_t>(obs.keyframe)];
    const auto& p = points[static_cast<std::size_t>(obs.point)];
    if (p->bad() || k->bad()) continue;
    const int index = p->IndexIn(k->id);
    if (index < 0) continue;
    k->EraseMapPoint(static_cast<std::size_t>(index));
    if (p->EraseObservation(k->id)) p->SetBad(map_);
  }
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    if (!problem.keyframes[k].fixed && !keyframes[k]->bad()) keyframes[k]->SetPose(result.T_c_w[k]);
  }
  for (std::size_t pi = 0; pi < points.size(); ++pi) {
    if (points[pi]->bad()) continue;
    points[pi]->SetPosition(result.p_w[pi]);
    points[pi]->UpdateNormalAndDepth();
  }
  return !result.aborted;
}

}  // namespace sgslam
