#include "sgslam/tracking/local_map.h"

#include <map>

#include "sgslam/matching/matcher.h"

namespace sgslam {

namespace {
constexpr std::size_t kMaxLocalKeyFrames = 80;
}

std::shared_ptr<KeyFrame> LocalMap::Update(const Frame& frame) {
  // Keyframes by the number of the frame's points they observe (ordered by id so
  // ties resolve the same way on every run).
  std::map<std::uint64_t, std::pair<std::shared_ptr<KeyFrame>, int>> counter;
  for (std::size_t i = 0; i < frame.map_points.size(); ++i) {
    const auto& p = frame.map_points[i];
    if (!p || p->bad()) continue;
    for (const auto& [kf_id, obs] : p->observations()) {
      auto& e = counter[kf_id];
      if (!e.first) e.first = obs.keyframe.lock();
      ++e.second;
    }
  }
  keyframes_.clear();
  std::shared_ptr<KeyFrame> reference;
  int best = 0;
  for (const auto& [id, e] : counter) {
    if (!e.first || e.first->bad()) continue;
    keyframes_.push_back(e.first);
    e.first->track_local_for_frame = frame.id;
    if (e.second > best) {
      best = e.second;
      reference = e.first;
    }
  }
  // Neighbours: best covisibles, children and parent of each (ORB-SLAM2).
  const std::size_t direct = keyframes_.size();
  const auto add = [&](const std::shared_ptr<KeyFrame>& kf) {
    if (!kf || kf->bad() || kf->track_local_for_frame == frame.id) return false;
    kf->track_local_for_frame = frame.id;
    keyframes_.push_back(kf);
    return true;
  };
  for (std::size_t k = 0; k < direct && keyframes_.size() < kMaxLocalKeyFrames; ++k) {
    const auto kf = keyframes_[k];
    for (const auto& n : kf->Covisibles(10)) {
      if (add(n)) break;
    }
    for (const auto& c : kf->children()) {
      if (add(c)) break;
    }
    add(kf->parent());
  }

  points_.clear();
  for (const auto& kf : keyframes_) {
    for (const auto& p : kf->map_points()) {
      if (!p || p->bad() || p->track.local_for_frame == frame.id) continue;
      p->track.local_for_frame = frame.id;
      points_.push_back(p);
    }
  }
  return reference;
}

int LocalMap::Search(Frame& frame, double th, int rejected_distance) {
  for (std::size_t i = 0; i < frame.map_points.size(); ++i) {
    const auto& p = frame.map_points[i];
    if (!p) continue;
    if (p->bad()) {
      frame.map_points[i].reset();
      continue;
    }
    p->IncreaseVisible();
    p->track.last_frame_seen = frame.id;
    p->track.in_view = false;
  }
  int to_match = 0;
  for (const auto& p : points_) {
    if (p->track.last_frame_seen == frame.id || p->bad()) continue;
    if (frame.IsInFrustum(*p, 0.5)) {
      p->IncreaseVisible();
      ++to_match;
    }
  }
  if (to_match == 0) return 0;
  return matcher::SearchLocalPoints(frame, points_, th, rejected_distance);
}

}  // namespace sgslam
