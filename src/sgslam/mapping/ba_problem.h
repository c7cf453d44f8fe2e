// Copying part of the map into a bundle-adjustment problem (optim/local_ba.h) and
// reading the solution back: the keyframes given are free, the other keyframes
// that see their points are fixed (ORB-SLAM2's local BA), the first keyframe is
// always fixed. Shared by local BA and the global BA that follows a loop.
//
// Threading: CopyBaProblem needs Map::mutex() held (shared at least).
#pragma once

#include <memory>
#include <vector>

#include "sgslam/map/map.h"
#include "sgslam/optim/local_ba.h"

namespace sgslam {

struct BaSnapshot {
  optim::BaProblem problem;
  std::vector<std::shared_ptr<KeyFrame>> keyframes;  // one per problem.keyframes
  std::vector<std::shared_ptr<MapPoint>> points;     // one per problem.points
};

BaSnapshot CopyBaProblem(const std::vector<std::shared_ptr<KeyFrame>>& free);

}  // namespace sgslam
