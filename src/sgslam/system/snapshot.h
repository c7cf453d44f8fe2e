// What a live viewer or a ROS node reads of a running system (docs/architecture.md,
// "Snapshots"): immutable copies. LatestFrame() takes no lock of the map;
// SnapshotMap() takes its shared lock on the reader's thread while it copies the
// poses and points, which tracking shares. SlamSystem::EnableSnapshots() turns the
// publishing on; LatestFrame() and SnapshotMap() may then be called from any thread.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "sgslam/common/se3.h"
#include "sgslam/common/time.h"
#include "sgslam/detection/detection.h"
#include "sgslam/movers/mover_tracker.h"
#include "sgslam/semantic/cloud.h"
#include "sgslam/semantic/objects.h"
#include "sgslam/tracking/tracker.h"

namespace sgslam {

// A mover track as of a frame (movers/mover_tracker.h), world (map) frame.
struct MoverSnapshot {
  int id = 0;
  std::string class_name;  // a COCO name or "unknown"
  movers::TrackState state = movers::TrackState::kTentative;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m, the centroid
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // m/s
  Eigen::Vector3d extent = Eigen::Vector3d::Zero();    // m, along the map axes
};

// The frame tracking finished last, with what the rejection made of it.
struct FrameSnapshot {
  enum Label : std::uint8_t { kKept = 0, kRejected = 1, kUnjudged = 2 };  // kUnjudged: kept without a test

  std::size_t index = 0;  // in the sequence
  Timestamp t = 0;
  TrackState state = TrackState::kNotInitialized;
  std::optional<SE3> T_w_c;             // when tracked
  cv::Mat bgr;                          // the colour image (shared, never written)
  std::vector<cv::Point2f> keypoints;   // px, raw (distorted) positions
  std::vector<std::uint8_t> labels;     // per keypoint, Label
  std::vector<Detection> detections;    // this frame's boxes, then those carried over missed detections
  std::vector<MoverSnapshot> movers;    // the mover tracks after this frame (none when it was not tracked)
  bool keyframe = false;                // a keyframe was made of it
  double frame_ms = 0;                  // the frame's time on the tracking thread
};

struct KeyFramePose {
  std::uint64_t id = 0;
  Timestamp t = 0;
  SE3 T_w_c;
};

// One keyframe's part of the static dense cloud, in its camera frame, placed with
// the keyframe's pose at the time of the snapshot.
struct CloudPiece {
  std::uint64_t keyframe_id = 0;
  SE3 T_w_c;
  std::shared_ptr<const std::vector<ColoredPoint>> points_c;
};

struct MapSnapshot {
  std::vector<KeyFramePose> keyframes;
  std::vector<Eigen::Vector3d> points;  // m, world: the sparse map points
  std::vector<CloudPiece> cloud;        // the semantic thread's keyframes so far (empty without it)
  std::vector<ObjectEstimate> objects;  // as of the semantic thread's last keyframe, world frame
  // The OctoMap's occupied cells as of that keyframe: centre (m, world) and side (m);
  // null without the semantic thread. Shared: the same pointer until it changes.
  std::shared_ptr<const std::vector<Eigen::Vector4f>> cells;
};

}  // namespace sgslam
