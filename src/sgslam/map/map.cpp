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

}  // namespace sgslam
