// The front of tracking in a dynamic scene (paper Fig. 1, Sec. III-A to III-D):
// every frame goes to the object detection thread as it arrives, tracking extracts
// ORB features meanwhile, runs Algorithm 1's flow (lines 1-2, no boxes needed),
// then waits (with a timeout) for the same frame's boxes and judges each keypoint
// static or dynamic (lines 3-14; dynamic/algorithm1.h).
//
// The mode is parsed once. None skips everything; geometric never needs the
// detector; semantic and sg use it when one is given, else they degrade (semantic
// to none, sg to geometric) with one warning. Around Algorithm 1 the stage applies
// the refinements R8-R12 of dynamic/refinements.h: the box area limit, the
// detector stride (boxes followed by the flow between detector frames), the carry
// of missed movers' boxes, the first frame judged by its boxes alone, then
// again with the second frame (DynamicOutcome::judged_again), and the mover
// tracks' predicted boxes in frames the detector did not see; and it keeps R3's
// prior of the previous frames' rejections. Their switches are
// DynamicConfig::refinements, their sizes constants of dynamic_stage.cpp. The current LK
// pyramid is kept as the next frame's previous one, so each image's pyramid is
// built once.
//
// Threading: all calls from the tracking thread; the detector runs on the
// DetectionWorker's thread (or inside Submit in sequential mode).
#pragma once

#include <algorithm>
#include <chrono>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "sgslam/detection/detection.h"
#include "sgslam/detection/detection_worker.h"
#include "sgslam/detection/detector.h"
#include "sgslam/detection/detector_config.h"
#include "sgslam/dynamic/box_carry.h"
#include "sgslam/dynamic/dynamic_config.h"
#include "sgslam/dynamic/algorithm1.h"
#include "sgslam/dynamic/refinements.h"
#include "sgslam/dynamic/undistort_table.h"

namespace sgslam {

class Camera;

struct DynamicOutcome {
  std::vector<std::uint8_t> dynamic;  // per keypoint: 1 = rejected (never tracked nor mapped)
  std::vector<std::uint8_t> unjudged;  // per keypoint: 1 = kept without a geometric test (Why::kUnjudged)
  // per keypoint: 1 = motion of its own, whatever box holds it: eq. (4) at w = 1
  // beyond eps_std, or flagged by the RGB-D check (the mover tracker's evidence)
  std::vector<std::uint8_t> moving;
  std::vector<Detection> detections;  // of this frame (empty without a detector or when late), then the carried ones
  int carried = 0;                    // of detections: missed moving-object boxes carried over (box_carry.h)
                                      // and the mover tracks' predicted boxes (movers/mover_tracker.h), last
  int predicted = 0;                  // of carried: the tracks' predicted boxes (R12)
  bool fresh_boxes = false;           // the detector ran on this frame and its boxes came in time
  int kept = 0, rejected_geometry = 0, rejected_semantics = 0, rejected_depth = 0;
  bool judged = false;        // Algorithm 1 ran (not the first frame, mode not none)
  bool detector_late = false;  // the wait timed out or the frame was dropped
  bool followed = false;       // not a detector frame (detector.stride): detections are the last ones moved with the flow
  double detector_ms = 0;      // inference time of this frame's detections
  double wait_ms = 0;          // time tracking waited for them
  double reject_ms = 0;        // flow (before the wait) + F + RGB-D check + decision
  // The frame after the first (dynamic.refinements.first_frame_rejudge): per keypoint of the
  // first frame, 1 where Algorithm 1, run on it with this frame as the other image,
  // judges it static (Tracker::ConfirmStaticInFirstKeyFrame clears those its boxes
  // rejected); empty otherwise.
  std::vector<std::uint8_t> static_in_first;
  // This frame was judged by its boxes alone (sg's first frame, no flow yet) and the
  // next Label judges it again (static_in_first).
  bool judged_again = false;
};

class DynamicStage {
 public:
  // detection: the class table and the wait for the detector; detector may be
  // null. Throws ConfigError for an unknown mode.
  DynamicStage(const DynamicConfig& config, const DetectorConfig& detection, std::shared_ptr<const Camera> camera,
               std::unique_ptr<Detector> detector, bool sequential);

  dynamic::Mode mode() const { return mode_; }
  bool has_detector() const { return worker_ != nullptr; }
  std::string DescribeDetector() const;

  // Hands the colour image to the detector on every (detector.stride x the stride
  // factor)-th call (no-op without one); the frames between follow the last boxes
  // and take the mover tracks' predicted ones (Label).
  void Submit(std::uint64_t frame_id, Timestamp t, const cv::Mat& bgr);
  // The factor of detector.stride (the CPU budget's throttle); from the next Submit.
  void SetStrideFactor(int factor) { stride_factor_ = std::max(1, factor); }

  // Labels the keypoints (raw, distorted positions) of the frame just submitted.
  // depth_raw feeds the RGB-D check (dynamic.refinements.depth_check). predicted:
  // the mover tracks' boxes for this frame (R12, dynamic.refinements.track_footprints),
  // used where no fresh detection of their class holds them.
  DynamicOutcome Label(std::uint64_t frame_id, const cv::Mat& gray, const cv::Mat& depth_raw,
                       const std::vector<cv::KeyPoint>& keys, const std::vector<Detection>& predicted = {});

  DetectionWorkerStats detector_stats() const;

 private:
  // Algorithm 1 lines 1-2 (pyramid, backward LK, pair filters, undistortion) into
  // cur.pyramid and the pairs; they need no boxes, so they run while the detector
  // works on the same frame (paper Fig. 1).
  dynamic::PairSet TrackFlow(const std::vector<cv::KeyPoint>& keys, dynamic::FlowFrame& cur) const;
  // The frame's detections (waited for with the timeout) and the carried boxes of
  // missed movers, into out.
  void AwaitDetections(std::uint64_t frame_id, const dynamic::PairSet& pairs, cv::Size image,
                       const std::vector<Detection>& predicted, DynamicOutcome& out);
  // This frame's detections or the followed ones (stride), then R10's carried boxes.
  void AwaitBoxes(std::uint64_t frame_id, const dynamic::PairSet& pairs, cv::Size image, DynamicOutcome& out);
  // Algorithm 1 lines 3-14 and the RGB-D check on this frame's pairs.
  dynamic::RejectionResult Judge(const dynamic::PairSet& pairs, const std::vector<cv::KeyPoint>& keys,
                                 const cv::Mat& depth_raw, cv::Size image, bool first,
                                 const std::vector<Detection>& detections);
  // w of Algorithm 1 for a box's class name in this mode.
  dynamic::WeightFn Weight() const;
  dynamic::UndistortPointsFn Undistort() const;
  dynamic::DepthCheckInput DepthInput(const cv::Mat& prev_depth, const cv::Mat& cur_depth) const;

  // dynamic.refinements.first_frame_rejudge: the first frame's keypoints that Algorithm 1
  // judges static with cur (this frame) as the other image.
  std::vector<std::uint8_t> JudgeFirstAgain(const dynamic::FlowFrame& cur, const cv::Mat& depth_raw,
                                            const dynamic::WeightFn& weight) const;

  // Per box, whether its keypoints show motion of their own (kCarryMinMotion).
  std::vector<bool> ShowMotion(const std::vector<cv::KeyPoint>& keys, const dynamic::RejectionResult& r,
                               const std::vector<Detection>& boxes) const;

  const DynamicConfig config_;
  const dynamic::Mode mode_;
  const bool wants_detector_;
  std::shared_ptr<const Camera> camera_;
  std::shared_ptr<const dynamic::UndistortTable> undistort_;  // raw -> undistorted flow pairs (distorted cameras)
  ClassTable classes_;
  const std::chrono::milliseconds timeout_;  // detector.timeout_ms
  const int stride_;                          // detector.stride
  int stride_factor_ = 1;                     // SetStrideFactor
  int since_detector_ = 0;                    // Submit calls since the last one that went to the detector
  std::unique_ptr<DetectionWorker> worker_;
  std::uint64_t submits_ = 0;  // Submit calls
  bool submitted_ = false;     // the frame being labelled went to the detector
  std::vector<Detection> last_boxes_;  // the last frame's detections (fresh or followed), for the frames between
  dynamic::FlowFrame prev_;
  bool boxes_only_ = false;  // prev_ was judged by its boxes alone and is judged again (R11)
  // That frame's keypoints and the boxes it was judged by, for its second judgment.
  std::vector<cv::KeyPoint> first_keys_;
  std::vector<Detection> first_boxes_;
  cv::Mat prev_depth_;
  dynamic::DynamicPrior prior_;  // R3, dynamic.refinements.prior_cells: the previous frames' rejections
  dynamic::BoxCarrier carrier_;  // R10, dynamic.refinements.box_carry
};

}  // namespace sgslam
