#include "sgslam/mapping/global_ba.h"

#include <deque>
#include <mutex>
#include <shared_mutex>

#include "sgslam/common/stats.h"
#include "sgslam/mapping/ba_problem.h"

namespace sgslam {

namespace {

// The correction of a point's reference keyframe or, that culled, of the first
// keyframe that sees it; null when none has one.
const SE3* DeltaOf(const MapPoint& p, const std::map<std::uint64_t, SE3>& delta) {
  if (const auto ref = p.reference_keyframe(); ref && !ref->bad()) {
    if (const auto it = delta.find(ref->id); it != delta.end()) return &it->second;
  }
  for (const auto& [kf_id, obs] : p.observations()) {
    if (const auto it = delta.find(kf_id); it != delta.end()) return &it->second;
  }
  return nullptr;
}

}  // namespace

GlobalBaResult SolveGlobalBa(const Map& map, int iterations, const std::function<bool()>& abort) {
  const Stopwatch watch;
  GlobalBaResult out;
  BaSnapshot snapshot;
  {
    std::shared_lock lock(map.mutex());
    std::vector<std::shared_ptr<KeyFrame>> all;
    for (const auto& [id, k] : map.keyframes()) {
      if (!k->bad()) all.push_back(k);
    }
    if (all.size() <= 2) return out;
    snapshot = CopyBaProblem(all);
  }
  optim::BaOptions options;
  options.first_iterations = iterations;
  options.second_iterations = iterations;
  const optim::BaResult r = optim::SolveLocalBa(snapshot.problem, options, abort);
  out.aborted = r.aborted;
  if (r.aborted) return out;
  for (std::size_t k = 0; k < snapshot.keyframes.size(); ++k) out.T_c_w[snapshot.keyframes[k]->id] = r.T_c_w[k];
  for (std::size_t p = 0; p < snapshot.points.size(); ++p) out.p_w[snapshot.points[p]->id] = r.p_w[p];
  out.keyframes = static_cast<int>(out.T_c_w.size());
  out.points = static_cast<int>(out.p_w.size());
  out.ms = watch.ElapsedMs();
  return out;
}

void ApplyGlobalBa(Map& map, const GlobalBaResult& result) {
  if (result.aborted || result.T_c_w.empty()) return;
  // New poses: the solution's, and for keyframes it did not have, the pose
  // relative to their parent kept (parents first: breadth-first from the root).
  std::map<std::uint64_t, SE3> next = result.T_c_w;
  std::deque<std::shared_ptr<KeyFrame>> todo;
  for (const auto& [id, k] : map.keyframes()) {
    if (!k->bad() && !k->parent()) todo.push_back(k);  // roots (the first keyframe)
  }
  while (!todo.empty()) {
    const auto k = todo.front();
    todo.pop_front();
    const auto mine = next.find(k->id);
    if (mine == next.end()) continue;
    for (const auto& child : k->children()) {
      if (child->bad()) continue;
      if (!next.count(child->id)) next[child->id] = child->T_c_w() * k->T_w_c() * mine->second;
      todo.push_back(child);
    }
  }
  // Old world -> new world, per keyframe, for the points that were not solved for.
  std::map<std::uint64_t, SE3> delta;
  SE3 newest;
  for (const auto& [id, T] : next) {
    const auto it = map.keyframes().find(id);
    if (it == map.keyframes().end() || it->second->bad()) continue;
    delta[id] = T.Inverse() * it->second->T_c_w();
    newest = delta[id];
  }
  const std::vector<std::shared_ptr<KeyFrame>> pending = PendingKeyFrames(map);
  for (const auto& k : pending) delta[k->id] = newest;
  for (const auto& [id, p] : map.map_points()) {
    if (p->bad()) continue;
    if (const auto solved = result.p_w.find(id); solved != result.p_w.end()) {
      p->SetPosition(solved->second);
    } else if (const SE3* d = DeltaOf(*p, delta)) {
      p->SetPosition(*d * p->position());
    } else {
      continue;
    }
    p->UpdateNormalAndDepth();
  }
  for (const auto& [id, D] : delta) {
    const auto it = map.keyframes().find(id);
    if (it != map.keyframes().end()) {
      it->second->SetPose(next.at(id));
    }
  }
  for (const auto& k : pending) k->SetPose(k->T_c_w() * newest.Inverse());
  map.NoteCorrection();
}

}  // namespace sgslam
