// Descriptor matching between frames, keyframes and map points (ORB-SLAM2's
// ORBmatcher). Distances are Hamming over 256-bit ORB.
//
// Threading: every function reads [map] fields; callers hold Map::mutex() shared
// (exclusive for Fuse, which changes associations).
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "sgslam/map/frame.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/map/map.h"
#include "sgslam/map/map_point.h"

namespace sgslam::matcher {

constexpr int kThHigh = 100;  // accept a match up to this distance
constexpr int kThLow = 50;    // ... where a stricter test is needed

// Rejected keypoints (Frame::rejected) are matched by the two projection searches
// only when rejected_distance > 0 (tracking.refinements.rejected_matches), in a second
// pass: to the trusted map points (MapPoint::track, tracking thread) that no kept
// keypoint matched, within that descriptor distance.

// Constant-velocity tracking: projects the last frame's matched points with the
// current pose estimate and searches within radius_px * scale of their level.
int SearchByProjection(Frame& current, const Frame& last, double radius_px, int rejected_distance);

// Relocalisation's guided search (ORB-SLAM2's SearchByProjection with a
// keyframe): the keyframe's points the frame has not matched, projected with the
// frame's pose, searched within radius_px * scale of their predicted level among
// the kept keypoints, up to max_distance; then rotation consistency.
int SearchByProjection(Frame& current, const KeyFrame& keyframe, double radius_px, int max_distance);

// Local-map tracking: `points` carry predictions from Frame::IsInFrustum; th
// scales the search radius. Skips keypoints already matched.
int SearchLocalPoints(Frame& current, const std::vector<std::shared_ptr<MapPoint>>& points, double th,
                      int rejected_distance);

// Reference-keyframe tracking without a pose prior worth trusting: the keyframe's
// mapped keypoints against all of the frame's, best distance below kThLow and
// below ratio * second best, then rotation consistency.
int SearchByDescriptor(const KeyFrame& keyframe, Frame& current, double ratio);

// The same, with the vocabulary's direct index (vocab/bow_vector.h): a keyframe
// keypoint is compared only with the frame's keypoints under the same tree node
// (ORB-SLAM2's SearchByBoW; about k^l times fewer comparisons). keyframe.bow set.
int SearchByBow(const KeyFrame& keyframe, Frame& current, const vocab::FeatureVector& current_nodes, double ratio);

// Projects points into the keyframe and fuses duplicates: a point landing on a
// keypoint that already has a point is merged into the one with more
// observations; otherwise the observation is added. Needs the exclusive lock.
int Fuse(const std::shared_ptr<KeyFrame>& keyframe, const std::vector<std::shared_ptr<MapPoint>>& points,
         Map& map, double th = 3.0);

// Pairs of keypoints without map points in kf1 and kf2 that satisfy the epipolar
// constraint of F_21 (x2^T F_21 x1 = 0) within the level's noise, for triangulation.
std::vector<std::pair<std::size_t, std::size_t>> SearchForTriangulation(const KeyFrame& kf1, const KeyFrame& kf2,
                                                                         const Eigen::Matrix3d& F_21);

// Loop closing: kf1's map points matched to kf2's through the direct index (both
// keypoints with a map point, best distance below kThLow and below ratio times the
// second best, rotation consistency). One entry per kf1 keypoint: kf2's point or null.
std::vector<std::shared_ptr<MapPoint>> SearchByBow(const KeyFrame& kf1, const KeyFrame& kf2, double ratio);

// Loop closing: points projected into kf at the pose T_c_w (its corrected pose),
// searched within th * scale of their predicted level, up to kThLow, among kf's
// keypoints that `matched` (one entry per keypoint) leaves free; the matches go
// into `matched`. Points already in `matched` are skipped. Returns the new matches.
int SearchByProjection(const KeyFrame& kf, const SE3& T_c_w, const std::vector<std::shared_ptr<MapPoint>>& points,
                       std::vector<std::shared_ptr<MapPoint>>& matched, double th);

// Keeps only matches whose keypoint-angle change falls in the three most
// populated bins of a 30-bin histogram (ORB-SLAM2, with the bin factor
// 30/360 that later forks fixed). Returns the indices (into `angle_diffs`) to drop.
std::vector<std::size_t> RotationOutliers(const std::vector<float>& angle_diffs);

}  // namespace sgslam::matcher
