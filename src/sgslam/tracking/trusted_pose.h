// Trusted map points: which matches may set a frame's pose.
//
// Two-frame tests (Algorithm 1, the RGB-D check) cannot see an object that moves
// less between two frames than the images' noise, such as a box pushed slowly
// along the view. Its keypoints pass, become map points at the next keyframe, and
// being fresh they agree with each other while the older static points, many of
// which a blurred view leaves as outliers, do not: the pose follows the object.
// Time separates them: a static point still fits the map a while after it was
// made, a moving one has left the place it was mapped at. So a map point earns
// trust by matching as a pose inlier `hits` times at least `delay` after its
// keyframe made it, and a frame's pose is fitted to the trusted matches first:
//   1. the trusted matches set the pose; every match is classified at it;
//   2. all matches are fitted again from there, those of step 1's inliers first;
//      the others may come back in later rounds when they fit (a static point
//      that step 1's coarser pose left just outside the bound).
// With fewer than min_trusted trusted matches (the start, a fast turn into new
// ground) every match sets the pose from the start, as in ORB-SLAM2.
//
// Threading: MapPoint::track is the tracking thread's; call from it only.
#pragma once

#include <memory>
#include <vector>

#include "sgslam/map/frame.h"
#include "sgslam/optim/pose_optimizer.h"

namespace sgslam {

struct TrustOptions {
  double delay_s = 0.3;  // 0: trust is off, every match sets the pose
  int hits = 2;
  int min_trusted = 20;
};

// obs[k] belongs to a map point that is trusted when trusted[k].
// trusted_start: whether step 1 ran (enough trusted matches).
optim::PoseOptimizationResult OptimizePoseTrusted(const SE3& T_c_w_initial, std::vector<optim::PoseObservation> obs,
                                                  const std::vector<bool>& trusted, const optim::Intrinsics& K,
                                                  const TrustOptions& options, bool* trusted_start = nullptr);

// After a frame's final pose: each untrusted map point matched as an inlier at
// least delay_s after it was made counts a hit; `hits` hits make it trusted.
void UpdateTrust(const Frame& frame, const TrustOptions& options);

// The points of the map's first keyframe set the world frame: trusted from the start.
void TrustAll(const std::vector<std::shared_ptr<MapPoint>>& points);

// Matched map points of the frame that are trusted and pose inliers.
int CountTrustedInliers(const Frame& frame);

}  // namespace sgslam
