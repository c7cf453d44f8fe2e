#include "sgslam/map/map.h"

namespace sgslam {

Map::~Map() { Clear(); }

void Map::Clear() {
  // Keyframes own their points strongly and everything else is weak, so dropping
  // the containers frees it all; clearing the keyframes' slots first keeps the
  // destruction shallow for large maps.
  for (auto& [id, kf] : keyframes_) {
    for (std::size_t i = 0; i < kf->map_points().size(); ++i) kf->EraseMapPoint(i);
  }
  keyframes_.clear();
  points_.clear();
}

std::vector<std::shared_ptr<KeyFrame>> PendingKeyFrames(const Map& map) {
  std::map<std::uint64_t, std::shared_ptr<KeyFrame>> pending;
  for (const auto& [id, p] : map.map_points()) {
    for (const auto& [kf_id, obs] : p->observations()) {
      if (map.keyframes().count(kf_id) || pending.count(kf_id)) continue;
      if (auto k = obs.keyframe.lock(); k && !k->bad()) pending[kf_id] = std::move(k);
    }
  }
  std::vector<std::shared_ptr<KeyFrame>> out;
  for (auto& [id, k] : pending) out.push_back(std::move(k));
  return out;
}

}  // namespace sgslam
