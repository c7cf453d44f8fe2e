#include "sgslam/map/map_point.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "sgslam/features/hamming.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/map/map.h"

namespace sgslam {

MapPoint::MapPoint(std::uint64_t point_id, const Eigen::Vector3d& p_w, const std::shared_ptr<KeyFrame>& reference)
    : id(point_id),
      first_keyframe_id(reference ? reference->id : 0),
      created_t(reference ? reference->t : 0),
      p_w_(p_w),
      reference_(reference) {}

MapPoint::MapPoint(std::uint64_t point_id, std::uint64_t first_kf_id, Timestamp created, const Eigen::Vector3d& p_w,
                   const Appearance& a)
    : id(point_id),
      first_keyframe_id(first_kf_id),
      created_t(created),
      p_w_(p_w),
      normal_(a.normal),
      min_distance_(a.min_distance),
      max_distance_(a.max_distance),
      visible_(a.visible),
      found_(a.found) {
  std::copy(a.descriptor.begin(), a.descriptor.end(), descriptor_);
}

MapPoint::Appearance MapPoint::appearance() const {
  Appearance a;
  a.normal = normal_;
  std::copy(descriptor_, descriptor_ + 32, a.descriptor.begin());
  a.min_distance = min_distance_;
  a.max_distance = max_distance_;
  a.visible = visible_.load(std::memory_order_relaxed);
  a.found = found_.load(std::memory_order_relaxed);
  return a;
}

int MapPoint::PredictScale(double distance, const ScaleLevels& scale) const {
  const double ratio = max_distance_ / std::max(distance, 1e-9);
  const int level = static_cast<int>(std::ceil(std::log(ratio) / scale.log_factor));
  return std::clamp(level, 0, scale.levels - 1);
}

void MapPoint::AddObservation(const std::shared_ptr<KeyFrame>& kf, std::size_t index) {
  if (observations_.count(kf->id)) return;
  const bool stereo = kf->features->u_right[index] >= 0;
  observations_[kf->id] = {kf, index, stereo};
  num_obs_ += stereo ? 2 : 1;
}

bool MapPoint::EraseObservation(std::uint64_t keyframe_id) {
  const auto it = observations_.find(keyframe_id);
  if (it == observations_.end()) return false;
  num_obs_ -= it->second.stereo ? 2 : 1;
  const auto ref = reference_.lock();
  observations_.erase(it);
  if ((!ref || ref->id == keyframe_id) && !observations_.empty()) reference_ = observations_.begin()->second.keyframe;
  return num_obs_ <= 2;
}

int MapPoint::IndexIn(std::uint64_t keyframe_id) const {
  const auto it = observations_.find(keyframe_id);
  return it == observations_.end() ? -1 : static_cast<int>(it->second.index);
}

void MapPoint::SetBad(Map& map) {
  bad_ = true;
  for (const auto& [kf_id, obs] : observations_) {
    if (const auto kf = obs.keyframe.lock(); kf && kf->map_point(obs.index).get() == this) kf->EraseMapPoint(obs.index);
  }
  observations_.clear();
  num_obs_ = 0;
  map.EraseMapPoint(id);
}

void MapPoint::ReplaceWith(const std::shared_ptr<MapPoint>& other, Map& map) {
  if (!other || other.get() == this) return;
  for (const auto& [kf_id, obs] : observations_) {
    const auto kf = obs.keyframe.lock();
    if (!kf) continue;
    if (other->IndexIn(kf_id) < 0) {
      kf->SetMapPoint(obs.index, other);
      other->AddObservation(kf, obs.index);
    } else {
      kf->EraseMapPoint(obs.index);  // both seen there: keep the other's association
    }
  }
  other->IncreaseFound(found_.load(std::memory_order_relaxed));
  other->IncreaseVisible(visible_.load(std::memory_order_relaxed));
  other->UpdateDescriptor();
  observations_.clear();
  num_obs_ = 0;
  bad_ = true;
  replaced_ = other;
  map.EraseMapPoint(id);
}

void MapPoint::UpdateDescriptor() {
  std::vector<const std::uint8_t*> descs;
  for (const auto& [kf_id, obs] : observations_) {
    if (const auto kf = obs.keyframe.lock(); kf && !kf->bad()) descs.push_back(kf->features->descriptor(obs.index));
  }
  if (descs.empty()) return;
  // The descriptor with the least median distance to all others (ORB-SLAM2).
  const std::size_t n = descs.size();
  std::vector<int> dist(n * n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) dist[i * n + j] = dist[j * n + i] = features::HammingDistance(descs[i], descs[j]);
  }
  int best_median = INT32_MAX;
  std::size_t best = 0;
  std::vector<int> row(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::copy(dist.begin() + i * n, dist.begin() + (i + 1) * n, row.begin());
    std::nth_element(row.begin(), row.begin() + (n - 1) / 2, row.end());
    if (row[(n - 1) / 2] < best_median) {
      best_median = row[(n - 1) / 2];
      best = i;
    }
  }
  std::copy(descs[best], descs[best] + 32, descriptor_);
}

void MapPoint::UpdateNormalAndDepth() {
  const auto ref = reference_.lock();
  if (!ref || observations_.empty()) return;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  int n = 0;
  for (const auto& [kf_id, obs] : observations_) {
    if (const auto kf = obs.keyframe.lock()) {
      normal += (p_w_ - kf->center()).normalized();
      ++n;
    }
  }
  const int ref_index = IndexIn(ref->id);
  if (n == 0 || ref_index < 0) return;
  normal_ = (normal / n).normalized();
  const ScaleLevels& scale = *ref->features->scale;
  const double distance = (p_w_ - ref->center()).norm();
  const int level = ref->features->keys_un[static_cast<std::size_t>(ref_index)].octave;
  max_distance_ = distance * scale.scale[static_cast<std::size_t>(level)];
  min_distance_ = max_distance_ / scale.scale.back();
}

}  // namespace sgslam
