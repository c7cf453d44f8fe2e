#include "sgslam/map/map.h"

namespace sgslam {

Map::~Map() { Clear(); }

void Map::Clear() {
  // Keyframes own their points strongly and everything else is weak, so dropping
  // the containers frees it all; clearing the keyframes' slots first keeps the
  // destruction shallow for large maps.
  for (auto* group : {&keyframes_, &pending_}) {
    for (auto& [id, kf] : *group) {
      for (std::size_t i = 0; i < kf->map_points().size(); ++i) kf->EraseMapPoint(i);
    }
  }
  keyframes_.clear();
  pending_.clear();
  points_.clear();
}

std::vector<std::shared_ptr<KeyFrame>> PendingKeyFrames(const Map& map) {
  std::vector<std::shared_ptr<KeyFrame>> out;
  for (const auto& [id, k] : map.pending()) {
    if (!k->bad()) out.push_back(k);
  }
  return out;
}

}  // namespace sgslam
