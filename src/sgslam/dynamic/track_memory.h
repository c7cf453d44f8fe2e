// Multi-frame motion evidence on top of Algorithm 1 (dynamic.track_check).
//
// Why: the two-frame tests (eq. 4 and the RGB-D check) see one frame step of
// motion, about 1 cm for a slowly moving object at 30 Hz. On the real fr1 frames of
// dyn_dev that overlaps the static noise (the unknown box: median epipolar distance
// 2.0 px, 25th percentile 0.66 px; static points: median 0.23 px, 90th percentile
// 0.9 px). A point that keeps moving accumulates its displacement linearly with the
// number of frames, while the noise of the chained camera motion grows about as
// the square root, so a test over several frames separates them.
//
// How: every keypoint carries an anchor, the 3-D point (camera coordinates) where
// its track was first seen with a clean depth, moved every frame by the
// frame-to-frame camera motion T_cur_prev: where a static point should be now. A
// keypoint continues the track of the previous frame's keypoint nearest to its
// backward flow position (within track_radius px times its pyramid scale); the
// anchor is shifted by the offset between that keypoint and the flow position, so
// that it follows the flow's point and not the neighbour's. Its
// residual is the distance (undistorted px) between the projected anchor and the
// keypoint; the track is judged moving when, at an age of at least track_min_age
// frames,
//   residual > track_tolerance + track_growth * sqrt(age).
// A track judged moving keeps its anchor (a mover's residual keeps growing); a
// static one is re-anchored every track_max_age frames so that the chained motion
// error stays small, and until it is old enough again it keeps its last verdict.
// Anchors are only taken where the 3x3 depth neighbourhood agrees (depth edges give
// a wrong depth and then a false parallax).
//
// The motion (track_motion): a PnP RANSAC of the carried anchors (tracks not judged
// moving, previous camera) onto the current keypoints. Two-frame fits (F, the PnP of
// the RGB-D check) pick the largest set that moved rigidly over one frame step; on
// dyn_dev that is the textured box whenever it holds more keypoints than the
// background left outside the person boxes, and then the background is "moving".
// Anchors of a mover started at different frames do not agree on one motion (each
// has moved by its own age times the object's step), static anchors of every age
// do, so this fit follows the background. Without track_motion, or with too few
// inliers, the caller's motion is used; without any motion the tracks restart.
//
// Measured on dyn_dev (off by default, numbers in dynamic_config.h): the tracks do
// separate the movers in general (age 1: box median residual 6 px, static 0.7 px
// after the anchor shift), but not where the ATE is lost. In frames 52-72 the box
// fills a fifth of the image, moves about 0.7 px a frame in it, and its textured
// keypoints live longer than the background's: the motion the tracks are carried
// by (two-frame PnP, or the anchor fit) follows the box, and there the static
// tracks drift away from their anchors (age 3: median 5.7 px) while the box's stay
// (1.4 px). The tracks need a reference that remembers the background over such a
// stretch (the map's long-observed points), not a better two-frame motion.
//
// Thread safety: one instance per tracking thread; deterministic for equal inputs.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "sgslam/common/se3.h"
#include "sgslam/dynamic/depth_check.h"
#include "sgslam/dynamic/dynamic_config.h"
#include "sgslam/dynamic/flow.h"

namespace sgslam::dynamic {

struct TrackVerdict {
  bool moving = false;  // judged moving (now, or carried while too young after a re-anchoring)
  int age = -1;         // frames since the anchor was set; -1: no anchor
  double residual = 0;  // px, projected anchor to keypoint (age > 0)
};

class TrackMemory {
 public:
  // keys: raw keypoints of the current frame; cur_un: their undistorted positions;
  // flow: backward pairs into the previous frame (raw), prev_un: flow.prev
  // undistorted; depth: current depth image
  // (CV_16U with depth_factor, or CV_32F metres); T_cur_prev: the camera motion
  // since the previous call, used when the tracks give none (nullopt: every track
  // restarts). One verdict per key.
  std::vector<TrackVerdict> Update(const std::vector<cv::KeyPoint>& keys, const std::vector<cv::Point2f>& cur_un,
                                   const FlowPairs& flow, const std::vector<cv::Point2f>& prev_un,
                                   const cv::Mat& depth, double depth_factor,
                                   const Pinhole& K, const std::optional<SE3>& T_cur_prev,
                                   const DynamicConfig& config);

  // The motion the last Update used, and whether the tracks gave it.
  const std::optional<SE3>& motion() const { return motion_; }
  bool motion_from_tracks() const { return motion_from_tracks_; }

 private:
  struct Track {
    cv::Point2f pt;     // raw px in the frame of the last Update
    cv::Point2f pt_un;  // the same undistorted
    Eigen::Vector3d anchor = Eigen::Vector3d::Zero();  // m, camera of that frame
    int age = -1;                                      // -1: no anchor
    bool moving = false;
  };
  // Index of the track nearest to p within r px, or -1.
  int Nearest(cv::Point2f p, double r) const;

  std::optional<SE3> FitMotion(const std::vector<Eigen::Vector3d>& anchors, const std::vector<cv::Point2f>& image,
                               const Pinhole& K, const DynamicConfig& config) const;

  std::vector<Track> tracks_;
  std::optional<SE3> motion_;
  bool motion_from_tracks_ = false;
  std::vector<std::vector<int>> grid_;  // track indices per cell (kCell px)
  int grid_cols_ = 0, grid_rows_ = 0;
};

}  // namespace sgslam::dynamic
