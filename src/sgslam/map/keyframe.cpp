#include "sgslam/map/keyframe.h"

#include <algorithm>
#include <set>
#include <stdexcept>

#include "sgslam/map/map.h"
#include "sgslam/map/map_point.h"

namespace sgslam {

namespace {
constexpr int kCovisibilityThreshold = 15;  // shared points for an edge (ORB-SLAM2)
}

KeyFrame::KeyFrame(std::uint64_t kf_id, std::uint64_t source_frame_id, Timestamp stamp,
                   std::shared_ptr<const Features> feats, const SE3& T_c_w)
    : id(kf_id), frame_id(source_frame_id), t(stamp), features(std::move(feats)), map_points_(features->size()) {
  SetPose(T_c_w);
}

void KeyFrame::ReplaceFeatures(std::shared_ptr<const Features> corrected) {
  if (!corrected || corrected->size() != features->size()) {
    throw std::invalid_argument("KeyFrame::ReplaceFeatures: the keypoints must stay the same");
  }
  features = std::move(corrected);
}

void KeyFrame::SetPose(const SE3& T_c_w) {
  T_c_w_ = T_c_w;
  T_w_c_translation_ = T_c_w.Inverse().translation();
}

int KeyFrame::TrackedMapPoints(int min_observations) const {
  int n = 0;
  for (const auto& p : map_points_) {
    if (p && !p->bad() && p->num_observations() >= min_observations) ++n;
  }
  return n;
}

void KeyFrame::UpdateConnections() {
  std::map<std::uint64_t, std::pair<std::shared_ptr<KeyFrame>, int>> counter;
  for (const auto& p : map_points_) {
    if (!p || p->bad()) continue;
    for (const auto& [kf_id, obs] : p->observations()) {
      if (kf_id == id) continue;
      auto& entry = counter[kf_id];
      if (!entry.first) {
        entry.first = obs.keyframe.lock();
        if (!entry.first || entry.first->bad()) {
          counter.erase(kf_id);
          continue;
        }
      }
      ++entry.second;
    }
  }
  if (counter.empty()) return;

  // Edges of at least the threshold weight, or the strongest one if none is.
  std::vector<std::pair<int, std::shared_ptr<KeyFrame>>> strong;
  std::pair<int, std::shared_ptr<KeyFrame>> best{0, nullptr};
  connections_.clear();
  for (const auto& [kf_id, entry] : counter) {
    connections_[kf_id] = {entry.first, entry.second};
    if (entry.second > best.first) best = {entry.second, entry.first};
    if (entry.second >= kCovisibilityThreshold) strong.emplace_back(entry.second, entry.first);
  }
  if (strong.empty()) strong.push_back(best);
  for (const auto& [w, kf] : strong) kf->AddConnection(shared_from_this(), w);
  std::sort(strong.begin(), strong.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second->id < b.second->id;
  });
  ordered_.clear();
  for (const auto& [w, kf] : strong) ordered_.emplace_back(w, kf);

  if (!has_parent_ && id != 0) {
    SetParent(strong.front().second);
  }
}

void KeyFrame::AddConnection(const std::shared_ptr<KeyFrame>& other, int weight) {
  auto it = connections_.find(other->id);
  if (it != connections_.end() && it->second.second == weight) return;
  connections_[other->id] = {other, weight};
  UpdateOrder();
}

void KeyFrame::EraseConnection(std::uint64_t other_id) {
  if (connections_.erase(other_id)) UpdateOrder();
}

void KeyFrame::UpdateOrder() {
  ordered_.clear();
  for (const auto& [kf_id, entry] : connections_) ordered_.emplace_back(entry.second, entry.first);
  // Stable order for equal weights: by id (connections_ iterates by id).
  std::stable_sort(ordered_.begin(), ordered_.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
}

std::vector<std::shared_ptr<KeyFrame>> KeyFrame::Covisibles(std::size_t n) const {
  std::vector<std::shared_ptr<KeyFrame>> out;
  for (const auto& [w, weak] : ordered_) {
    if (out.size() >= n) break;
    if (auto kf = weak.lock(); kf && !kf->bad()) out.push_back(std::move(kf));
  }
  return out;
}

std::vector<std::shared_ptr<KeyFrame>> KeyFrame::CovisiblesWithWeight(int min_weight) const {
  std::vector<std::shared_ptr<KeyFrame>> out;
  for (const auto& [w, weak] : ordered_) {
    if (w < min_weight) break;
    if (auto kf = weak.lock(); kf && !kf->bad()) out.push_back(std::move(kf));
  }
  return out;
}

std::vector<std::uint64_t> KeyFrame::ConnectedIds() const {
  std::vector<std::uint64_t> out;
  out.reserve(connections_.size());
  for (const auto& [other, entry] : connections_) out.push_back(other);
  return out;
}

std::vector<std::shared_ptr<KeyFrame>> KeyFrame::LoopEdges() const {
  std::vector<std::shared_ptr<KeyFrame>> out;
  for (const auto& [other, kf] : loop_edges_) {
    if (auto k = kf.lock(); k && !k->bad()) out.push_back(std::move(k));
  }
  return out;
}

int KeyFrame::Weight(std::uint64_t other_id) const {
  const auto it = connections_.find(other_id);
  return it == connections_.end() ? 0 : it->second.second;
}

std::vector<std::shared_ptr<KeyFrame>> KeyFrame::children() const {
  std::vector<std::shared_ptr<KeyFrame>> out;
  for (const auto& [cid, weak] : children_) {
    if (auto kf = weak.lock()) out.push_back(std::move(kf));
  }
  return out;
}

void KeyFrame::SetParent(const std::shared_ptr<KeyFrame>& parent) {
  if (const auto old = parent_.lock()) old->EraseChild(id);
  parent_ = parent;
  has_parent_ = parent != nullptr;
  if (parent) parent->AddChild(shared_from_this());
}

void KeyFrame::AddChild(const std::shared_ptr<KeyFrame>& child) { children_[child->id] = child; }
void KeyFrame::EraseChild(std::uint64_t child_id) { children_.erase(child_id); }

std::vector<std::pair<std::uint64_t, int>> KeyFrame::CovisibleOrder() const {
  std::vector<std::pair<std::uint64_t, int>> out;
  for (const auto& [w, weak] : ordered_) {
    if (const auto kf = weak.lock()) out.emplace_back(kf->id, w);
  }
  return out;
}

void KeyFrame::RestoreConnections(const Edges& connections, const Edges& order) {
  connections_.clear();
  for (const auto& [kf, w] : connections) connections_[kf->id] = {kf, w};
  ordered_.clear();
  for (const auto& [kf, w] : order) ordered_.emplace_back(w, kf);
}

void KeyFrame::RestoreCulled(std::shared_ptr<KeyFrame> parent, const SE3& T_c_parent) {
  bad_ = true;
  T_c_parent_ = T_c_parent;
  parent_when_culled_ = std::move(parent);
}

void KeyFrame::SetBad(Map& map) {
  if (id == 0 || bad_ || !loop_edges_.empty()) return;  // the first keyframe anchors the map; loops hold theirs
  for (const auto& [kf_id, entry] : connections_) {
    if (const auto other = entry.first.lock()) other->EraseConnection(id);
  }
  for (std::size_t i = 0; i < map_points_.size(); ++i) {
    const auto p = map_points_[i];
    if (p && p->EraseObservation(id)) p->SetBad(map);
  }
  connections_.clear();
  ordered_.clear();

  // Re-attach the children: each goes to the candidate parent it shares most
  // points with, candidates growing from the old parent (ORB-SLAM2's SetBadFlag).
  const auto parent = parent_.lock();
  std::set<std::uint64_t> candidate_ids;
  std::vector<std::shared_ptr<KeyFrame>> candidates;
  if (parent) {
    candidate_ids.insert(parent->id);
    candidates.push_back(parent);
  }
  std::vector<std::shared_ptr<KeyFrame>> remaining = children();
  while (!remaining.empty() && !candidates.empty()) {
    int best_weight = -1;
    std::shared_ptr<KeyFrame> best_child, best_parent;
    for (const auto& child : remaining) {
      if (child->bad()) continue;
      for (const auto& cov : child->Covisibles()) {
        if (!candidate_ids.count(cov->id)) continue;
        const int w = child->Weight(cov->id);
        if (w > best_weight) {
          best_weight = w;
          best_child = child;
          best_parent = cov;
        }
      }
    }
    if (!best_child) break;
    best_child->SetParent(best_parent);
    candidate_ids.insert(best_child->id);
    candidates.push_back(best_child);
    remaining.erase(std::find(remaining.begin(), remaining.end(), best_child));
  }
  for (const auto& child : remaining) child->SetParent(parent);  // no shared points: the old parent
  if (parent) {
    parent->EraseChild(id);
    T_c_parent_ = T_c_w_ * parent->T_w_c();
    parent_when_culled_ = parent;
  }
  children_.clear();
  bad_ = true;
  map.EraseKeyFrame(id);
}

SE3 KeyFrame::PlacedT_c_w() const {
  SE3 T_c_r;
  const KeyFrame* ref = this;
  while (ref->bad() && ref->parent_when_culled()) {
    T_c_r = T_c_r * ref->T_c_parent();
    ref = ref->parent_when_culled().get();
  }
  return T_c_r * ref->T_c_w();
}

}  // namespace sgslam
