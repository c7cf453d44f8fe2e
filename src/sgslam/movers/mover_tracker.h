// The movers as live 3-D tracks: each person (a detected box of a moving-object
// class) and each unknown mover (a cluster of keypoints that showed motion of
// their own, e.g. dyn_dev's box) becomes a track with an id, a class, its 3-D
// points, centroid, extent and velocity in the map frame, and a state.
//
// Per frame with a pose (Update):
//   1 observations: the depth inside each fresh dynamic-class box, cut to the
//     mover's depth band (the person, not the wall behind: SegmentBox), and the
//     clusters of moving keypoints outside those boxes (ClusterMovingKeypoints);
//   2 association in 3-D: each observation to the nearest compatible track's
//     predicted centroid within kGate (greedy, nearest pair first);
//   3 a constant-velocity model in the map frame: the centroid is the last
//     observation's, the velocity the least-squares slope over the last
//     kVelocityWindow observations, followed for at most Track::kHorizon;
//   4 states: tentative until kConfirmHits observations of which kConfirmEvidence
//     showed motion of their own (a person sitting still stays tentative);
//     confirmed while observed or coasting (kCoast); lost after that, still
//     predicted; forgotten after kForget without an observation.
// Between (Footprints): a confirmed or lost track's 3-D points, moved by its
// velocity to the next frame's time and projected with the predicted pose, give a
// box with the track's class weight; the dynamic stage puts it in Algorithm 1 in
// place of a box the detector did not give (dynamic.refinements.track_footprints).
//
// Thread safety: none; one instance, driven from the tracking thread (its cost is
// the depth samples of a few boxes: a fraction of a millisecond).
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "sgslam/camera/camera.h"
#include "sgslam/common/se3.h"
#include "sgslam/common/time.h"
#include "sgslam/detection/detection.h"
#include "sgslam/detection/detector_config.h"

namespace sgslam::movers {

enum class TrackState : std::uint8_t { kTentative, kConfirmed, kLost };
const char* StateName(TrackState state);

constexpr char kUnknownClass[] = "unknown";  // a mover the detector has no box for

// One mover seen in one frame.
struct Observation {
  std::string class_name;               // the box's class, or kUnknownClass for a keypoint cluster
  cv::Rect2f box;                       // px, raw image: the detection, or the cluster's keypoints
  std::vector<Eigen::Vector3d> points;  // map frame: the depth samples on the mover (at most kMaxPoints)
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // mean of points
  Eigen::Vector3d extent = Eigen::Vector3d::Zero();    // m, per map axis: the 10-90 % range of points
  bool moving = false;  // showed motion of its own (a cluster always; a box: kMinMovingShare of its keypoints)
  int source = -1;      // the box's index in FrameInput::boxes; -1 for a cluster
  int guided = -1;      // cut at this track's predicted depth, for it alone; -1: the box's foreground
};

struct Track {
  int id = 0;
  std::string class_name;
  TrackState state = TrackState::kTentative;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m, map frame: the centroid at `updated`
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // m/s, map frame
  Eigen::Vector3d extent = Eigen::Vector3d::Zero();    // m
  std::vector<Eigen::Vector3d> points;                 // relative to position, map axes
  Timestamp born = 0, updated = 0;                     // first and last observation
  int hits = 0, moving_hits = 0;                       // observations, those that showed motion
  int misses = 0;                                      // frames with a pose since the last observation
  bool observed = false;                               // in the last Update
  std::deque<std::pair<Timestamp, Eigen::Vector3d>> history;  // the last observed centroids

  // The constant-velocity prediction, for at most kHorizon after the last
  // observation: a velocity fitted on a partly seen mover is not to be followed far.
  static constexpr double kHorizon = 0.2;  // s
  Eigen::Vector3d PositionAt(Timestamp t) const {
    return position + velocity * std::min(kHorizon, ToSeconds(t - updated));
  }
};

// What a frame gives the tracker. keys: raw keypoints; depth: m per keypoint
// (<= 0 none); moving: 1 where the keypoint showed motion of its own (eq. 4 at
// w = 1 beyond eps_std, or the RGB-D check; DynamicOutcome::moving); boxes: this
// frame's detections (carried and predicted boxes, carried > 0, are not observations);
// fresh_boxes: the detector ran on this frame (not a stride or late frame).
struct FrameInput {
  Timestamp t = 0;
  SE3 T_c_w;
  const std::vector<cv::KeyPoint>* keys = nullptr;
  const std::vector<float>* depth = nullptr;
  const std::vector<std::uint8_t>* moving = nullptr;
  const std::vector<Detection>* boxes = nullptr;
  bool fresh_boxes = false;
  cv::Mat depth_raw;  // CV_16U, the frame's depth image
};

struct TrackerStats {
  int tracks = 0, confirmed = 0;  // ever started, ever confirmed
  int observations = 0, box_observations = 0, cluster_observations = 0;
};

class MoverTracker {
 public:
  MoverTracker(std::shared_ptr<const Camera> camera, ClassTable classes)
      : camera_(std::move(camera)), classes_(std::move(classes)) {}

  // A frame with a pose: observe, associate, update, age.
  void Update(const FrameInput& in);
  // A frame without a pose (tracking lost): the tracks age, nothing is observed.
  void Skip(Timestamp t);

  // The predicted boxes (raw px, carried = 1, class and score of the track) of the
  // confirmed and lost tracks at time t seen from T_c_w; none for a track whose
  // points fall outside the image or behind the camera.
  std::vector<Detection> Footprints(const SE3& T_c_w, Timestamp t) const;

  // The live tracks (tentative, confirmed and lost), by id.
  const std::vector<Track>& tracks() const { return tracks_; }
  const TrackerStats& stats() const { return stats_; }

  // Step 1, exposed for the tests.
  std::vector<Observation> Observe(const FrameInput& in) const;

 private:
  // The mover in box `box` of in.boxes at seed_depth (0: the box's foreground).
  bool BoxObservation(const FrameInput& in, int box, double seed_depth, Observation& o) const;
  bool SegmentBox(const cv::Mat& depth_raw, const cv::Rect2f& box, double seed_depth, const SE3& T_w_c,
                  Observation& out) const;
  void MergeDuplicates();
  void Age(Timestamp t);

  std::shared_ptr<const Camera> camera_;
  ClassTable classes_;
  std::vector<Track> tracks_;
  int next_id_ = 1;
  TrackerStats stats_;
};

}  // namespace sgslam::movers
