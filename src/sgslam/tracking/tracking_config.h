// Tracking: ORB-SLAM2's RGB-D tracking, whose settings are named constants beside
// their use (tracker.cpp, keyframe_decision.cpp). What a config file may set are
// the refinements beyond ORB-SLAM2, each switchable for an ablation
// (docs/algorithm1.md, "In tracking").
#pragma once

#include "sgslam/common/config_checker.h"

namespace sgslam {

struct TrackingRefinements {
  // Map points earn the right to set the pose (trusted_pose.h): a point is trusted
  // once it has matched as a pose inlier a few times some time after its keyframe
  // made it; the first keyframe's points are trusted. A mover that passes every
  // two-frame test is caught by the time it has moved. Off: ORB-SLAM2, every match
  // sets the pose.
  bool trusted_points = true;
  // A keypoint that dynamic rejection condemned may still match a trusted map point
  // that no kept keypoint matched (within a close descriptor distance): a point that
  // stayed where the map put it is static, while the two-frame tests condemn static
  // keypoints whose flow went wrong in blur. Rejected keypoints never make map
  // points. Off: never matched (the paper).
  bool rejected_matches = true;
  // With a rolling-shutter camera (camera.readout > 0), keypoints are first
  // corrected with the predicted angular velocity; this fits the frame's angular
  // velocity together with its pose, corrects them again and fits the pose once more.
  bool rolling_shutter_refine = true;
  // With a rolling shutter, a new keyframe goes to local mapping one frame late,
  // its keypoints corrected again with the central difference of the poses on
  // either side (the fitted velocity lags by a frame and a half).
  bool keyframe_velocity_central = true;
  // The same for every frame's exported pose: frame n is fitted again once frame
  // n+1 is tracked (trajectory.txt; trajectory_online.txt keeps the live pose).
  bool frame_velocity_central = true;

  template <class V>
  void Visit(V&& v) {
    v("trusted_points", trusted_points, "map points earn trust before they set the pose alone (off: ORB-SLAM2)");
    v("rejected_matches", rejected_matches, "rejected keypoints may match trusted map points no kept keypoint matched");
    v("rolling_shutter_refine", rolling_shutter_refine, "fit the frame's angular velocity with its pose and correct the keypoints again");
    v("keyframe_velocity_central", keyframe_velocity_central, "correct a keyframe one frame later with the velocity of the frames around it");
    v("frame_velocity_central", frame_velocity_central, "fit every frame again one frame later with the velocity of the frames around it (trajectory.txt)");
  }
};

struct TrackingConfig {
  // When the map cannot be matched (movers cover most of the image, the camera
  // looks where the map has no points), the pose comes from the frame before by
  // visual odometry on its kept keypoints with depth outside the movers' boxes, until
  // the map is matched again (frames.csv state `odometry`). Off: such a frame has no
  // pose (ORB-SLAM2's way). On by default: measured on the dynamic panel
  // (docs/tracking-states.md).
  bool odometry_fallback = true;
  TrackingRefinements refinements;

  template <class V>
  void Visit(V&& v) {
    v("odometry_fallback", odometry_fallback,
      "a frame the map cannot be matched in takes its pose from the frame before (visual odometry) instead of none");
    v("refinements", refinements, "beyond ORB-SLAM2's tracking, each switchable (docs/algorithm1.md)");
  }
  void Validate(ConfigChecker&) const {}
};

}  // namespace sgslam
