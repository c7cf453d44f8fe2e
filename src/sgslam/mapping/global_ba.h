// The global bundle adjustment that follows a loop closure (ORB-SLAM2's
// RunGlobalBundleAdjustment), in two steps so that the solve holds no lock:
// SolveGlobalBa copies every keyframe and point (under the map's shared lock) and
// optimises them, the first keyframe fixed, abortable between iterations;
// ApplyGlobalBa (map lock held exclusively, local mapping paused by the caller)
// writes the result back. Keyframes made while it ran follow their parent through
// the spanning tree; those local mapping has not inserted yet, the newest
// keyframe's correction; points made meanwhile follow their reference keyframe.
#pragma once

#include <cstdint>
#include <functional>
#include <map>

#include "sgslam/map/map.h"

namespace sgslam {

struct GlobalBaResult {
  std::map<std::uint64_t, SE3> T_c_w;              // per keyframe id
  std::map<std::uint64_t, Eigen::Vector3d> p_w;    // per point id
  bool aborted = false;
  int keyframes = 0, points = 0;
  double ms = 0;
};

GlobalBaResult SolveGlobalBa(const Map& map, int iterations, const std::function<bool()>& abort);
void ApplyGlobalBa(Map& map, const GlobalBaResult& result);

}  // namespace sgslam
