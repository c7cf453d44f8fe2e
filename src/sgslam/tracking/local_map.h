// The local map of the tracked frame: keyframes that share points with it and
// their neighbours, and the points they see (ORB-SLAM2's UpdateLocalMap).
// Tracking thread only; the caller holds Map::mutex() shared.
#pragma once

#include <memory>
#include <vector>

#include "sgslam/map/frame.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/map/map_point.h"

namespace sgslam {

class LocalMap {
 public:
  // Rebuilds the local keyframes and points around the frame's matches and returns
  // the keyframe sharing most points with it (the new reference), or nullptr.
  std::shared_ptr<KeyFrame> Update(const Frame& frame);

  // Projects the local points into the frame and matches those in view; returns
  // the number of new matches. rejected_distance: matcher::SearchLocalPoints.
  int Search(Frame& frame, double th, int rejected_distance);

 private:
  std::vector<std::shared_ptr<KeyFrame>> keyframes_;
  std::vector<std::shared_ptr<MapPoint>> points_;
};

}  // namespace sgslam
