#include "sgslam/loop/loop_closer.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <shared_mutex>

#include <spdlog/spdlog.h>

#include "sgslam/common/stats.h"
#include "sgslam/geometry/rigid.h"
#include "sgslam/matching/matcher.h"
#include "sgslam/optim/pose_graph.h"
#include "sgslam/optim/pose_optimizer.h"

namespace sgslam {

namespace {

constexpr double kBowRatio = 0.75;            // SearchByBow's best/second ratio (ORB-SLAM2)
constexpr double kLoopSearchRadius = 10;      // px at level 0, the neighbourhood's points
constexpr double kFuseRadius = 4;             // px at level 0, loop fusion
constexpr int kEssentialCovisibility = 100;   // shared points for a covisibility edge in the graph
constexpr double kChi2Rigid = 9.210;          // 99 % of chi2 with 2 dof

geometry::Pinhole PinholeOf(const KeyFrame& kf) {
  const Camera& c = *kf.features->camera;
  return {c.fx(), c.fy(), c.cx(), c.cy()};
}

double Sigma2(const KeyFrame& kf, std::size_t i) {
  const Features& f = *kf.features;
  return f.scale->sigma2[static_cast<std::size_t>(f.keys_un[i].octave)];
}

// The points of a keyframe and its covisible neighbours, each once.
std::vector<std::shared_ptr<MapPoint>> NeighbourhoodPoints(const std::shared_ptr<KeyFrame>& kf) {
  std::vector<std::shared_ptr<MapPoint>> out;
  std::set<std::uint64_t> seen;
  std::vector<std::shared_ptr<KeyFrame>> group = kf->Covisibles();
  group.insert(group.begin(), kf);
  for (const auto& k : group) {
    for (const auto& p : k->map_points()) {
      if (p && !p->bad() && seen.insert(p->id).second) out.push_back(p);
    }
  }
  return out;
}

// The relative pose T_i_j of two poses T_i_w and T_j_w.
SE3 Relative(const SE3& T_i_w, const SE3& T_j_w) { return T_i_w * T_j_w.Inverse(); }

// The keyframes and the points they see move with a rigid correction of the world
// (x -> correction * x); each point once.
// Returns, per point moved, the keyframe that moved it: the pose graph then moves
// the point with that keyframe (ORB-SLAM2's mnCorrectedReference), not again with
// its reference keyframe, which may be outside the neighbourhood.
std::map<std::uint64_t, std::uint64_t> MoveRigidly(const std::vector<std::shared_ptr<KeyFrame>>& connected,
                                                   const std::vector<std::shared_ptr<KeyFrame>>& pending,
                                                   const SE3& correction) {
  std::map<std::uint64_t, std::uint64_t> moved_by;
  for (const auto* group : {&connected, &pending}) {
    for (const auto& k : *group) {
      for (const auto& p : k->map_points()) {
        if (p && !p->bad() && moved_by.emplace(p->id, k->id).second) p->SetPosition(correction * p->position());
      }
    }
  }
  for (const auto* group : {&connected, &pending}) {
    for (const auto& k : *group) k->SetPose(k->T_c_w() * correction.Inverse());
  }
  for (const auto& p : connected.front()->map_points()) {
    if (p && !p->bad()) p->UpdateNormalAndDepth();
  }
  return moved_by;
}

// The optimised poses to the keyframes (pending ones move with `current`), and each
// point with its reference keyframe (or, that culled, the first keyframe seeing it).
void ApplyPoseGraph(Map& map, const std::vector<std::shared_ptr<KeyFrame>>& nodes,
                    const optim::PoseGraphProblem& problem, const optim::PoseGraphResult& result,
                    const std::vector<std::shared_ptr<KeyFrame>>& pending, const std::shared_ptr<KeyFrame>& current,
                    const std::map<std::uint64_t, std::uint64_t>& moved_by) {
  std::map<std::uint64_t, SE3> delta;  // T_w_c_new * T_c_w_now: old world -> new world, per keyframe
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    delta[nodes[n]->id] = result.T_c_w[n].Inverse() * problem.nodes[n].T_c_w;
    nodes[n]->SetPose(result.T_c_w[n]);
  }
  const SE3 current_delta = delta.at(current->id);
  for (const auto& k : pending) {
    delta[k->id] = current_delta;
    k->SetPose(k->T_c_w() * current_delta.Inverse());
  }
  for (const auto& [id, p] : map.map_points()) {
    if (p->bad()) continue;
    auto it = delta.end();
    if (const auto by = moved_by.find(id); by != moved_by.end()) {
      it = delta.find(by->second);
    } else if (const auto ref = p->reference_keyframe(); ref && !ref->bad()) {
      it = delta.find(ref->id);
    }
    for (auto o = p->observations().begin(); it == delta.end() && o != p->observations().end(); ++o) {
      it = delta.find(o->first);
    }
    if (it == delta.end()) continue;
    p->SetPosition(it->second * p->position());
    p->UpdateNormalAndDepth();
  }
}

}  // namespace

std::optional<VerifiedLoop> LoopCloser::Detect(const std::shared_ptr<KeyFrame>& kf, LoopReport& report) {
  const Stopwatch watch;
  report.keyframe = kf->id;
  std::shared_lock lock(map_.mutex());
  if (kf->bad() || !kf->bow || map_.keyframes().size() < kMinKeyFrames ||
      (loops_closed_ > 0 && kf->id < last_loop_kf_ + kMinKeyFrames)) {
    return std::nullopt;
  }
  // The worst score of a neighbour: a loop candidate must look at least as alike.
  double min_score = 1;
  for (const auto& n : kf->Covisibles()) {
    if (n->bow) min_score = std::min(min_score, vocab::Score(kf->bow->words, n->bow->words));
  }
  const std::vector<PlaceCandidate> candidates = places_->LoopCandidates(*kf, min_score);
  report.candidates = static_cast<int>(candidates.size());
  const std::vector<std::shared_ptr<KeyFrame>> consistent = ConsistentCandidates(candidates);
  report.consistent = static_cast<int>(consistent.size());
  spdlog::debug("loop: keyframe {} (frame {}): min score {:.3f}, {} candidates{}, {} consistent", kf->id, kf->frame_id,
                min_score, candidates.size(), candidates.empty() ? "" : fmt::format(" (best {} {:.3f})", candidates[0].keyframe->id, candidates[0].score),
                consistent.size());
  std::optional<VerifiedLoop> loop;
  for (const auto& candidate : consistent) {
    loop = Verify(kf, candidate);
    if (loop && Plausible(*loop)) break;
    report.implausible += loop.has_value();
    loop.reset();
    ++report.rejected;
  }
  if (report.rejected > 0) {
    spdlog::debug("keyframe {}: {} consistent loop candidate(s) failed geometric verification", kf->id,
                  report.rejected);
  }
  report.detect_ms = watch.ElapsedMs();
  if (loop) {
    report.inliers = loop->inliers;
    report.loop_keyframe = loop->loop->id;
    report.frame = kf->frame_id, report.t = kf->t;
    report.loop_frame = loop->loop->frame_id, report.loop_t = loop->loop->t;
  }
  return loop;
}

bool LoopCloser::Plausible(const VerifiedLoop& loop) const {
  // The path: the live keyframes made between the two, in order.
  double path = 0;
  std::optional<Eigen::Vector3d> last;
  for (auto it = map_.keyframes().lower_bound(loop.loop->id); it != map_.keyframes().end(); ++it) {
    if (it->first > loop.current->id) break;
    if (it->second->bad()) continue;
    if (last) path += (it->second->center() - *last).norm();
    last = it->second->center();
  }
  const SE3 correction = loop.T_c_w.Inverse() * loop.current->T_c_w();
  const double moved = (loop.T_c_w.Inverse().translation() - loop.current->center()).norm();
  const double turned = correction.Log().tail<3>().norm() * 180.0 / M_PI;
  const bool ok = moved <= kMaxDriftBase + kMaxDriftRatio * path && turned <= kMaxTurnBase + kMaxTurnPerMetre * path;
  if (!ok) {
    spdlog::info("loop candidate rejected: frame {} and frame {} look alike and fit ({} inliers), but the correction "
                 "of {:.2f} m and {:.1f} deg after {:.2f} m travelled is more than drift explains",
                 loop.current->frame_id, loop.loop->frame_id, loop.inliers, moved, turned, path);
  }
  return ok;
}

std::vector<std::shared_ptr<KeyFrame>> LoopCloser::ConsistentCandidates(const std::vector<PlaceCandidate>& candidates) {
  std::vector<std::shared_ptr<KeyFrame>> enough;
  std::vector<Group> current;
  std::vector<bool> continued(groups_.size(), false);
  for (const PlaceCandidate& c : candidates) {
    const std::vector<std::uint64_t> ids = c.keyframe->ConnectedIds();
    std::set<std::uint64_t> group(ids.begin(), ids.end());
    group.insert(c.keyframe->id);
    bool consistent_with_some = false, added = false;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      const auto& previous = groups_[g].first;
      const bool shares = std::any_of(group.begin(), group.end(), [&](std::uint64_t id) { return previous.count(id); });
      if (!shares) continue;
      consistent_with_some = true;
      const int consistency = groups_[g].second + 1;
      if (!continued[g]) {
        current.emplace_back(group, consistency);
        continued[g] = true;
      }
      if (consistency >= kConsistency && !added) {
        enough.push_back(c.keyframe);
        added = true;
      }
    }
    if (!consistent_with_some) current.emplace_back(group, 0);
  }
  groups_ = std::move(current);
  return enough;
}

std::optional<VerifiedLoop> LoopCloser::Verify(const std::shared_ptr<KeyFrame>& kf,
                                               const std::shared_ptr<KeyFrame>& candidate) {
  std::vector<std::shared_ptr<MapPoint>> matched = matcher::SearchByBow(*kf, *candidate, kBowRatio);
  geometry::RigidRansacProblem problem{{}, PinholeOf(*kf), PinholeOf(*candidate)};
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < matched.size(); ++i) {
    const auto& own = kf->map_point(i);
    if (!matched[i] || !own || own->bad()) continue;
    const int j = matched[i]->IndexIn(candidate->id);
    if (j < 0) continue;
    const auto& k1 = kf->features->keys_un[i].pt;
    const auto& k2 = candidate->features->keys_un[static_cast<std::size_t>(j)].pt;
    problem.matches.push_back({kf->T_c_w() * own->position(), candidate->T_c_w() * matched[i]->position(),
                               {k1.x, k1.y}, {k2.x, k2.y}, kChi2Rigid * Sigma2(*kf, i),
                               kChi2Rigid * Sigma2(*candidate, static_cast<std::size_t>(j))});
    index.push_back(i);
  }
  spdlog::debug("loop check {} -> {}: {} bow matches", kf->id, candidate->id, problem.matches.size());
  if (static_cast<int>(problem.matches.size()) < kMinBowMatches) return std::nullopt;
  geometry::RigidRansacOptions options;
  options.min_inliers = kMinBowMatches;
  options.seed = static_cast<std::uint32_t>(kf->id);
  const auto rigid = geometry::EstimateRigidRansac(problem, options);
  if (!rigid) return std::nullopt;
  spdlog::debug("  ransac {} inliers", rigid->inliers);
  // Only the RANSAC's inliers, then the keyframe's pose fitted to the loop side's points.
  std::vector<std::shared_ptr<MapPoint>> kept(matched.size());
  for (std::size_t m = 0; m < index.size(); ++m) {
    if (rigid->inlier[m]) kept[index[m]] = matched[index[m]];
  }
  SE3 T_c_w = rigid->T_12 * candidate->T_c_w();
  if (FitPose(*kf, kept, T_c_w) < kMinBowMatches) return std::nullopt;
  // More matches from the candidate's neighbourhood, at that pose; a last fit.
  VerifiedLoop loop{kf, candidate, T_c_w, SE3(), std::move(kept), NeighbourhoodPoints(candidate), 0};
  matcher::SearchByProjection(*kf, loop.T_c_w, loop.loop_points, loop.matched, kLoopSearchRadius);
  loop.inliers = FitPose(*kf, loop.matched, loop.T_c_w);
  loop.T_cur_loop = loop.T_c_w * candidate->T_w_c();
  spdlog::debug("  final {} inliers", loop.inliers);
  if (loop.inliers < kMinLoopInliers) return std::nullopt;
  return loop;
}

int LoopCloser::FitPose(const KeyFrame& kf, std::vector<std::shared_ptr<MapPoint>>& matched, SE3& T_c_w) {
  const Features& f = *kf.features;
  std::vector<optim::PoseObservation> obs;
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < matched.size(); ++i) {
    if (!matched[i]) continue;
    optim::PoseObservation o;
    o.p_w = matched[i]->position();
    o.uv = {f.keys_un[i].pt.x, f.keys_un[i].pt.y};
    o.u_right = f.u_right[i];
    o.inv_sigma2 = f.scale->inv_sigma2[static_cast<std::size_t>(f.keys_un[i].octave)];
    obs.push_back(o);
    index.push_back(i);
  }
  if (obs.size() < 3) return 0;
  const Camera& c = *f.camera;
  const auto r = optim::OptimizePose(T_c_w, obs, {c.fx(), c.fy(), c.cx(), c.cy(), c.baseline_fx()});
  T_c_w = r.T_c_w;
  for (std::size_t k = 0; k < index.size(); ++k) {
    if (!r.inlier[k]) matched[index[k]].reset();
  }
  return r.inliers;
}

void LoopCloser::Correct(const VerifiedLoop& loop, LoopReport& report) {
  const Stopwatch watch;
  std::unique_lock lock(map_.mutex());
  const auto& current = loop.current;
  if (current->bad() || loop.loop->bad()) {
    ++report.rejected;  // culled while it was verified
    return;
  }
  current->UpdateConnections();
  std::vector<std::shared_ptr<KeyFrame>> connected = current->Covisibles();
  connected.insert(connected.begin(), current);
  // Keyframes tracking made that local mapping has not inserted: their points are
  // in the map, they are not (yet).
  const std::vector<std::shared_ptr<KeyFrame>> pending = PendingKeyFrames(map_);
  // The current keyframe's neighbourhood (and the pending keyframes) move rigidly
  // with it, world points x -> correction * x.
  const SE3 target = loop.T_cur_loop * loop.loop->T_c_w();  // the loop side as it is now
  const SE3 correction = target.Inverse() * current->T_c_w();
  const Vector6d step = correction.Log();
  report.correction_m = (target.Inverse().translation() - current->center()).norm();
  report.correction_deg = step.tail<3>().norm() * 180.0 / M_PI;
  std::map<std::uint64_t, SE3> before;  // poses before the correction, for the graph's edges
  for (const auto& [id, k] : map_.keyframes()) before[id] = k->T_c_w();
  const auto moved_by = MoveRigidly(connected, pending, correction);
  const auto new_links = FuseAndLink(loop, connected, report);
  OptimizeEssentialGraph(loop, before, new_links, pending, moved_by, report);
  current->AddLoopEdge(loop.loop);
  loop.loop->AddLoopEdge(current);
  last_loop_kf_ = current->id;
  ++loops_closed_;
  map_.NoteCorrection();
  report.closed = true;
  report.correct_ms = watch.ElapsedMs();
}

std::map<std::uint64_t, std::set<std::uint64_t>> LoopCloser::FuseAndLink(
    const VerifiedLoop& loop, const std::vector<std::shared_ptr<KeyFrame>>& connected, LoopReport& report) {
  std::map<std::uint64_t, std::set<std::uint64_t>> previous;
  std::set<std::uint64_t> group;
  for (const auto& k : connected) {
    const auto ids = k->ConnectedIds();
    previous[k->id] = std::set<std::uint64_t>(ids.begin(), ids.end());
    group.insert(k->id);
  }
  FuseLoopPoints(loop, connected, report);
  std::map<std::uint64_t, std::set<std::uint64_t>> new_links;
  for (const auto& k : connected) {
    k->UpdateConnections();
    for (const std::uint64_t id : k->ConnectedIds()) {
      if (!previous[k->id].count(id) && !group.count(id)) new_links[k->id].insert(id);
    }
  }
  return new_links;
}

void LoopCloser::FuseLoopPoints(const VerifiedLoop& loop, const std::vector<std::shared_ptr<KeyFrame>>& connected,
                                LoopReport& report) {
  const auto& current = loop.current;
  for (std::size_t i = 0; i < loop.matched.size(); ++i) {
    const auto& p = loop.matched[i];
    if (!p || p->bad()) continue;
    if (const auto own = current->map_point(i); own && !own->bad()) {
      if (own != p) own->ReplaceWith(p, map_), ++report.fused;  // the loop side's point is the older
    } else if (p->IndexIn(current->id) < 0) {
      current->SetMapPoint(i, p);
      p->AddObservation(current, i);
      p->UpdateDescriptor();
    }
  }
  for (const auto& k : connected) report.fused += matcher::Fuse(k, loop.loop_points, map_, kFuseRadius);
}

void LoopCloser::OptimizeEssentialGraph(const VerifiedLoop& loop, const std::map<std::uint64_t, SE3>& before,
                                        const std::map<std::uint64_t, std::set<std::uint64_t>>& new_links,
                                        const std::vector<std::shared_ptr<KeyFrame>>& pending,
                                        const std::map<std::uint64_t, std::uint64_t>& moved_by, LoopReport& report) {
  const Stopwatch watch;
  optim::PoseGraphProblem problem;
  std::vector<std::shared_ptr<KeyFrame>> nodes;
  std::map<std::uint64_t, SE3> now;  // poses after the rigid correction: loop edges use these
  for (const auto& [id, k] : map_.keyframes()) {
    if (k->bad()) continue;
    nodes.push_back(k);
    now[id] = k->T_c_w();
    problem.nodes.push_back({id, k->T_c_w(), k == loop.loop});
  }
  const auto old_pose = [&](std::uint64_t id) {
    const auto it = before.find(id);
    return it != before.end() ? it->second : now.at(id);
  };
  std::set<std::pair<std::uint64_t, std::uint64_t>> added;
  // An edge between two live keyframes, measured with `pose` (the poses after the
  // rigid correction for the loop's new links, before it for the others).
  const auto add = [&](std::uint64_t i, std::uint64_t j, const auto& pose) {
    if (i == j || !now.count(i) || !now.count(j)) return;
    if (!added.insert({std::min(i, j), std::max(i, j)}).second) return;
    problem.edges.push_back({i, j, Relative(pose(i), pose(j)), 1.0});
  };
  const auto now_pose = [&](std::uint64_t id) { return now.at(id); };
  for (const auto& [i, links] : new_links) {
    for (const std::uint64_t j : links) add(i, j, now_pose);
  }
  for (const auto& k : nodes) {
    if (const auto parent = k->parent(); parent && !parent->bad()) add(k->id, parent->id, old_pose);
    for (const auto& l : k->LoopEdges()) add(k->id, l->id, old_pose);
    for (const auto& n : k->CovisiblesWithWeight(kEssentialCovisibility)) add(k->id, n->id, old_pose);
  }
  const optim::PoseGraphResult result = optim::OptimizePoseGraph(problem);
  report.corrected_keyframes = static_cast<int>(nodes.size());
  report.pose_graph_ms = watch.ElapsedMs();
  if (!result.success) {
    spdlog::warn("loop {} -> {}: the pose graph did not converge; only the neighbourhood was corrected",
                 loop.current->id, loop.loop->id);
    return;
  }
  ApplyPoseGraph(map_, nodes, problem, result, pending, loop.current, moved_by);
}

}  // namespace sgslam
