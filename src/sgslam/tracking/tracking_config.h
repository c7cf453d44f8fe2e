// Tracking (ORB-SLAM2's RGB-D settings unless a comment says otherwise).
#pragma once

#include "sgslam/common/config_checker.h"

namespace sgslam {

struct TrackingConfig {
  int min_init_points = 500;           // keypoints with depth needed to start the map (at most half of orb.features)
  double motion_search_radius = 15.0;  // px at level 0, constant-velocity projection search
  // factor, local-map projection search (ORB-SLAM2: 3): under fast rotation the
  // rolling shutter shifts rows by pixels.
  double local_search_radius = 5.0;
  double descriptor_ratio = 0.7;       // best/second-best ratio, reference keyframe matching
  int min_motion_matches = 20;         // matches needed to trust the motion model
  int min_pose_inliers = 10;           // inliers after pose optimisation (motion / reference)
  int min_local_inliers = 30;          // inliers after local-map tracking
  int recover_candidates = 30;         // keyframes tried per frame while lost without place recognition (loop.enabled false): newest 5, then nearest
  double keyframe_ref_ratio = 0.75;    // new keyframe when tracked points fall below this share of the reference's
  int max_frames_between_keyframes = 30;  // frames; 0: the camera's fps
  int close_tracked_min = 100;         // need a keyframe when fewer close points are tracked ...
  int close_untracked_min = 70;        // ... and at least this many close points are not
  int keyframe_min_new_points = 100;   // points created per keyframe beyond the close range
  bool skip_outlier_depth_points = true;  // no new keyframe point from a pose-outlier keypoint (dynamic modes only)
  // Map points earn the right to set the pose (trusted_pose.h): a point is trusted
  // once it has matched as a pose inlier trust_hits times at least trust_delay
  // after its keyframe made it; the first keyframe's points are trusted. A mover
  // that passes every two-frame test is caught by the time it has moved. 0: off
  // (ORB-SLAM2: every match sets the pose).
  double trust_delay = 0.3;   // s
  int trust_hits = 2;         // late inlier matches that make a point trusted
  int trust_min_points = 20;  // trusted matches a frame needs to be fitted to them first; fewer: all matches
  // bits; a keypoint that dynamic rejection condemned may still match a trusted map
  // point that no kept keypoint matched, within this descriptor distance: a point
  // that stayed where the map put it is static, while the two-frame tests condemn
  // static keypoints whose flow went wrong in blur. Rejected keypoints never make
  // map points. 0: never matched (the paper).
  int rejected_match_distance = 50;
  // With a rolling-shutter camera (camera.readout > 0), keypoints are first
  // corrected with the predicted angular velocity; this fits the frame's angular
  // velocity together with its pose, corrects them again and fits the pose once more.
  bool rolling_shutter_refine = true;
  double rolling_shutter_prior = 1.0;  // rad/s, sigma of the refined velocity around the predicted one
  // With a rolling shutter, a new keyframe goes to local mapping one frame late,
  // its keypoints corrected again with the central difference of the poses on
  // either side (the fitted velocity lags by a frame and a half).
  bool keyframe_velocity_central = true;
  // The same for every frame's exported pose: frame n is fitted again once frame
  // n+1 is tracked (trajectory.txt; trajectory_online.txt keeps the live pose).
  bool frame_velocity_central = true;

  template <class V>
  void Visit(V&& v) {
    v("min_init_points", min_init_points, "keypoints with depth to start the map");
    v("motion_search_radius", motion_search_radius, "px, motion-model search radius");
    v("local_search_radius", local_search_radius, "factor, local-map search radius");
    v("descriptor_ratio", descriptor_ratio, "best/second ratio, reference keyframe matching");
    v("min_motion_matches", min_motion_matches, "matches to trust the motion model");
    v("min_pose_inliers", min_pose_inliers, "inliers after pose optimisation");
    v("min_local_inliers", min_local_inliers, "inliers after local-map tracking");
    v("recover_candidates", recover_candidates, "keyframes tried per frame while lost, without place recognition");
    v("keyframe_ref_ratio", keyframe_ref_ratio, "tracked share of the reference keyframe's points");
    v("max_frames_between_keyframes", max_frames_between_keyframes, "frames between keyframes at most");
    v("close_tracked_min", close_tracked_min, "close points tracked, keyframe rule");
    v("close_untracked_min", close_untracked_min, "close points untracked, keyframe rule");
    v("keyframe_min_new_points", keyframe_min_new_points, "points created per keyframe");
    v("skip_outlier_depth_points", skip_outlier_depth_points, "no keyframe point from a pose-outlier keypoint");
    v("trust_delay", trust_delay, "s, age at which a map point's inlier matches start to earn it trust; 0: off");
    v("trust_hits", trust_hits, "late inlier matches that make a map point trusted");
    v("trust_min_points", trust_min_points, "trusted matches needed to fit a frame's pose to them first");
    v("rejected_match_distance", rejected_match_distance, "bits; rejected keypoints may match trusted map points no kept keypoint matched within it; 0: never");
    v("rolling_shutter_refine", rolling_shutter_refine, "fit the frame's angular velocity with its pose and correct the keypoints again");
    v("rolling_shutter_prior", rolling_shutter_prior, "rad/s, sigma of the fitted angular velocity around the predicted one");
    v("keyframe_velocity_central", keyframe_velocity_central, "correct a keyframe one frame later with the velocity of the frames around it");
    v("frame_velocity_central", frame_velocity_central, "fit every frame again one frame later with the velocity of the frames around it (exported trajectory)");
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
