#include "sgslam/mapping/local_mapper.h"

#include <mutex>
#include <set>
#include <shared_mutex>

#include "sgslam/common/stats.h"
#include "sgslam/matching/matcher.h"

namespace sgslam {

namespace {

constexpr int kFusionNeighbours = 10;  // covisible keyframes (and theirs) searched for duplicates (ORB-SLAM2)
// A keyframe is culled when this share of its points is seen by three other
// keyframes (ORB-SLAM2).
constexpr double kRedundantRatio = 0.9;

}  // namespace

LocalMapper::LocalMapper(const MappingConfig& config, double close_depth, Map& map,
                         std::shared_ptr<KeyFrameDatabase> places)
    : config_(config), map_(map), places_(std::move(places)), th_depth_(close_depth) {}

MappingStats LocalMapper::Process(const std::shared_ptr<KeyFrame>& kf, const std::function<bool()>& interrupted) {
  Stopwatch watch;
  MappingStats stats;
  Stopwatch step;
  InsertKeyFrame(kf);
  stats.culled_points = CullRecentPoints(kf);
  stats.insert_ms = step.ElapsedMs();
  step.Restart();
  stats.new_points = CreateNewMapPoints(kf);
  stats.triangulate_ms = step.ElapsedMs();
  step.Restart();
  if (!interrupted()) stats.fused = SearchInNeighbors(kf);
  stats.fuse_ms = step.ElapsedMs();
  if (!interrupted()) {
    step.Restart();
    stats.ba_done = true;
    stats.ba_aborted = !LocalBundleAdjustment(kf, interrupted, stats);
    stats.ba_ms = step.ElapsedMs();
    step.Restart();
    stats.culled_keyframes = CullKeyFrames(kf);
    stats.cull_ms = step.ElapsedMs();
  }
  stats.ms = watch.ElapsedMs();
  return stats;
}

void LocalMapper::InsertKeyFrame(const std::shared_ptr<KeyFrame>& kf) {
  // The descriptors never change once the keyframe is here (keyframe.h).
  const auto bow = places_ ? places_->Describe(kf->features->descriptors) : nullptr;
  std::unique_lock lock(map_.mutex());
  kf->bow = bow;
  for (std::size_t i = 0; i < kf->map_points().size(); ++i) {
    const auto& p = kf->map_point(i);
    if (!p) continue;
    if (p->bad()) {
      kf->EraseMapPoint(i);
      continue;
    }
    if (p->IndexIn(kf->id) < 0) {  // a tracked point: add this keyframe's view
      p->AddObservation(kf, i);
      p->UpdateNormalAndDepth();
      p->UpdateDescriptor();
    } else {  // created with the keyframe: watch whether it holds up
      recent_points_.push_back(p);
    }
  }
  kf->UpdateConnections();
  map_.AddKeyFrame(kf);
  if (places_) places_->Add(kf);
}

int LocalMapper::CullRecentPoints(const std::shared_ptr<KeyFrame>& kf) {
  // A new point must be found in at least a quarter of the frames that predicted
  // it, and be seen by 3+ keyframes once two more keyframes came (ORB-SLAM2).
  std::unique_lock lock(map_.mutex());
  int culled = 0;
  for (auto it = recent_points_.begin(); it != recent_points_.end();) {
    const auto& p = *it;
    const std::uint64_t age = kf->id - p->first_keyframe_id;
    if (p->bad()) {
      it = recent_points_.erase(it);
    } else if (p->FoundRatio() < 0.25 || (age >= 2 && p->num_observations() <= 3)) {
      p->SetBad(map_);
      ++culled;
      it = recent_points_.erase(it);
    } else if (age >= 3) {
      it = recent_points_.erase(it);
    } else {
      ++it;
    }
  }
  return culled;
}

int LocalMapper::SearchInNeighbors(const std::shared_ptr<KeyFrame>& kf) {
  std::unique_lock lock(map_.mutex());
  const int n = kFusionNeighbours;
  std::vector<std::shared_ptr<KeyFrame>> targets;
  std::set<std::uint64_t> seen = {kf->id};
  for (const auto& k : kf->Covisibles(static_cast<std::size_t>(n))) {
    if (!seen.insert(k->id).second) continue;
    targets.push_back(k);
  }
  const std::size_t first = targets.size();
  for (std::size_t t = 0; t < first; ++t) {
    for (const auto& k2 : targets[t]->Covisibles(5)) {
      if (seen.insert(k2->id).second) targets.push_back(k2);
    }
  }
  int fused = 0;
  // Copies: fusion reassigns keyframe slots, which must not alias the list walked.
  const std::vector<std::shared_ptr<MapPoint>> own = kf->map_points();
  for (const auto& target : targets) fused += matcher::Fuse(target, own, map_);
  std::vector<std::shared_ptr<MapPoint>> candidates;
  std::set<std::uint64_t> taken;
  for (const auto& target : targets) {
    for (const auto& p : target->map_points()) {
      if (p && !p->bad() && taken.insert(p->id).second) candidates.push_back(p);
    }
  }
  fused += matcher::Fuse(kf, candidates, map_);
  for (const auto& p : kf->map_points()) {
    if (!p || p->bad()) continue;
    p->UpdateDescriptor();
    p->UpdateNormalAndDepth();
  }
  kf->UpdateConnections();
  return fused;
}

int LocalMapper::CullKeyFrames(const std::shared_ptr<KeyFrame>& kf) {
  // A keyframe whose close points are seen, at the same or a finer scale, by at
  // least three other keyframes adds nothing (ORB-SLAM2's KeyFrameCulling).
  std::unique_lock lock(map_.mutex());
  int culled = 0;
  for (const auto& k : kf->Covisibles()) {
    if (k->id == 0 || k->bad()) continue;
    const Features& f = *k->features;
    int points = 0, redundant = 0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      const auto& p = k->map_point(i);
      if (!p || p->bad() || f.depth[i] <= 0 || f.depth[i] > th_depth_) continue;
      ++points;
      if (p->num_observations() <= 3) continue;
      const int level = f.keys_un[i].octave;
      int others = 0;
      for (const auto& [other_id, obs] : p->observations()) {
        if (other_id == k->id) continue;
        const auto other = obs.keyframe.lock();
        if (!other || other->bad()) continue;
        if (other->features->keys_un[obs.index].octave <= level + 1 && ++others >= 3) break;
      }
      if (others >= 3) ++redundant;
    }
    if (points > 0 && redundant > kRedundantRatio * points) {
      k->SetBad(map_);  // refused for a keyframe that closes a loop
      if (!k->bad()) continue;
      if (places_) places_->Erase(*k);
      ++culled;
    }
  }
  return culled;
}

}  // namespace sgslam
