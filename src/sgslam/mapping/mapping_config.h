// Local mapping: ORB-SLAM2's, whose settings are named constants beside their use
// (local_mapper.cpp, new_points.cpp, local_ba.cpp, slam_system.cpp).
#pragma once

#include "sgslam/common/config_checker.h"

namespace sgslam {

struct MappingConfig {
  // One bundle adjustment of the whole map when the sequence ends (what ORB-SLAM2
  // runs after a loop closure), iterations per stage; 0: off. Only trajectory.txt
  // and the maps see it; trajectory_online.txt is what tracking output at the time.
  int final_ba_iterations = 10;
  // A bound on the map's size for long runs in one place (a robot's patrol): once
  // the map holds this many keyframes it stops growing and later frames are tracked
  // in it, as with --localize. 0: no bound.
  int max_keyframes = 0;

  template <class V>
  void Visit(V&& v) {
    v("final_ba_iterations", final_ba_iterations, "global BA iterations per stage when the sequence ends; 0: off");
    v("max_keyframes", max_keyframes, "keyframes at which the map stops growing and frames are only tracked in it; 0: no bound");
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
