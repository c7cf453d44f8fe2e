#include "sgslam/system/dynamic_stage.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "sgslam/camera/camera.h"
#include "sgslam/common/stats.h"
#include "sgslam/movers/mover_tracker.h"

namespace sgslam {

namespace {

// The sizes of the refinements the stage applies around Algorithm 1
// (dynamic/refinements.h; switched by DynamicConfig::refinements).
// R3 (b): px, cells of the previous image where most keypoints were rejected stay
// out of the F and PnP fits; one dyn_dev run measured (docs/algorithm1.md R3).
constexpr int kPriorCell = 20;
// R3 (b): frames a rejected keypoint keeps its cell out while its flow-tracked
// successors are kept: a slow mover can pass eq. (4) in one frame (5 of 1, 3, 5, 8 measured).
constexpr int kPriorMemory = 5;
// R8: share of the image above which a box takes no part: a box that large is most
// likely a false detection and has no outside to contrast with (0.4-0.7 measured).
constexpr double kMaxBoxArea = 0.7;
// R10: frames a missed moving-object box is carried (measured at 8 against off).
constexpr int kCarryFrames = 8;
// R10: IoU of a fresh detection of its class that replaces a carried box.
constexpr double kCarryIou = 0.3;
// R10: share of a box's keypoints that must show motion of their own (beyond eps_std
// unweighted, or flagged by the RGB-D check) for it to be carried: not a false box.
constexpr double kCarryMinMotion = 0.2;
// R12: w of a track's predicted box when the track has no class (a mover only the
// geometry found): the least weight of a moving-object class.
const std::vector<Detection> kNoBoxes;
constexpr double kUnknownMoverWeight = ClassTable::kMinWeight;

}  // namespace

DynamicStage::DynamicStage(const DynamicConfig& config, const DetectorConfig& detection,
                           std::shared_ptr<const Camera> camera, std::unique_ptr<Detector> detector, bool sequential)
    : config_(config),
      mode_(dynamic::ParseMode(config.mode)),
      wants_detector_(mode_ == dynamic::Mode::kSemantic || mode_ == dynamic::Mode::kSg),
      camera_(std::move(camera)),
      classes_(detection),
      timeout_(detection.timeout_ms),
      stride_(detection.stride),
      carrier_(config.refinements.box_carry ? kCarryFrames : 0, kCarryIou,
               [table = ClassTable(detection)](const std::string& name) { return table.is_dynamic(name); }) {
  if (camera_->has_distortion() && config.refinements.undistort_pairs && mode_ != dynamic::Mode::kNone &&
      mode_ != dynamic::Mode::kSemantic) {
    undistort_ = std::make_shared<const dynamic::UndistortTable>(
        cv::Size(camera_->width(), camera_->height()),
        [cam = camera_](std::vector<cv::Point2f>& p) { cam->Undistort(p); });
  }
  if (wants_detector_ && detector) {
    DetectionWorker::Options options;
    options.sequential = sequential;
    worker_ = std::make_unique<DetectionWorker>(std::move(detector), options);
  } else if (wants_detector_) {
    spdlog::warn("mode {} without a detector: {}", config.mode,
                 mode_ == dynamic::Mode::kSg ? "the epipolar test alone decides (as --mode geometric)"
                                             : "nothing is rejected (as --mode none)");
  }
}

std::string DynamicStage::DescribeDetector() const { return worker_ ? worker_->Describe() : "none"; }

void DynamicStage::Submit(std::uint64_t frame_id, Timestamp t, const cv::Mat& bgr) {
  submitted_ = worker_ && (submits_++ == 0 || since_detector_ + 1 >= stride_ * stride_factor_);
  since_detector_ = submitted_ ? 0 : since_detector_ + 1;
  if (submitted_) worker_->Submit(frame_id, t, bgr);
}

DetectionWorkerStats DynamicStage::detector_stats() const { return worker_ ? worker_->stats() : DetectionWorkerStats{}; }

std::vector<bool> DynamicStage::ShowMotion(const std::vector<cv::KeyPoint>& keys, const dynamic::RejectionResult& r,
                                           const std::vector<Detection>& boxes) const {
  // Semantic mode has no geometry to ask, so it carries nothing: carrying every box
  // there would reject so much that tracking is lost.
  if (mode_ == dynamic::Mode::kSemantic) return std::vector<bool>(boxes.size(), false);
  constexpr int kMinKeypoints = 5;  // fewer in a box: no verdict, not carried
  const DynamicConfig& c = config_;
  std::vector<bool> moving(boxes.size(), false);
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    int inside = 0, evidence = 0;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (!boxes[b].box.contains(keys[i].pt)) continue;
      ++inside;
      // Motion the box's weight did not make: eq. (4) beyond eps_std itself, or the RGB-D check.
      const dynamic::KeypointVerdict& v = r.keypoints[i];
      evidence += v.why == dynamic::Why::kDepth || (std::isfinite(v.distance) && v.distance >= c.eps_std);
    }
    moving[b] = inside >= kMinKeypoints && evidence >= kCarryMinMotion * inside;
  }
  return moving;
}

std::vector<std::uint8_t> DynamicStage::JudgeFirstAgain(const dynamic::FlowFrame& cur, const cv::Mat& depth_raw,
                                                       const dynamic::WeightFn& weight) const {
  // Algorithm 1 for the first frame's keypoints, with this frame as the other image:
  // LK from them into this image, F and the RGB-D check on those pairs, eq. (4)
  // with the boxes the first frame was judged by.
  std::vector<std::uint8_t> now_static(first_keys_.size(), 0);
  if (first_keys_.empty() || prev_depth_.empty()) return now_static;
  const dynamic::PairSet pairs = dynamic::TrackPairs(cur, prev_, first_keys_, config_, Undistort());
  const dynamic::DepthCheckInput depth = DepthInput(depth_raw, prev_depth_);
  const dynamic::RejectionResult r = dynamic::JudgePairs(mode_, pairs, first_keys_, first_boxes_, weight, config_,
                                                         config_.refinements.depth_check ? &depth : nullptr);
  for (std::size_t i = 0; i < first_keys_.size(); ++i) {
    now_static[i] = r.keypoints[i].kept && r.keypoints[i].why == dynamic::Why::kStatic;
  }
  return now_static;
}

dynamic::WeightFn DynamicStage::Weight() const {
  // Algorithm 1 weighs a point by the largest w of the boxes holding it (a chair's
  // w = 2 too); semantic mode removes only the boxes of moving-object classes.
  // A mover track of no class weighs as the least moving class (R12).
  if (mode_ == dynamic::Mode::kSemantic) {
    return [this](const std::string& name) {
      if (name == movers::kUnknownClass) return kUnknownMoverWeight;
      return classes_.is_dynamic(name) ? classes_.weight(name) : 1.0;
    };
  }
  return [this](const std::string& name) {
    return name == movers::kUnknownClass ? kUnknownMoverWeight : classes_.weight(name);
  };
}

dynamic::UndistortPointsFn DynamicStage::Undistort() const {
  if (!undistort_) return {};
  return [table = undistort_](std::vector<cv::Point2f>& p) { table->Apply(p); };
}

dynamic::DepthCheckInput DynamicStage::DepthInput(const cv::Mat& prev_depth, const cv::Mat& cur_depth) const {
  dynamic::DepthCheckInput depth;
  depth.prev_depth = prev_depth;
  depth.cur_depth = cur_depth;
  depth.depth_factor = camera_->config().depth_factor;
  depth.K = {camera_->fx(), camera_->fy(), camera_->cx(), camera_->cy()};
  return depth;
}

dynamic::PairSet DynamicStage::TrackFlow(const std::vector<cv::KeyPoint>& keys, dynamic::FlowFrame& cur) const {
  if (mode_ == dynamic::Mode::kSemantic) return {};
  cur.pyramid = dynamic::BuildFlowPyramid(cur.gray);
  if (prev_.gray.empty()) return {};  // the first frame: no flow
  return dynamic::TrackPairs(prev_, cur, keys, config_, Undistort());
}

void DynamicStage::AwaitDetections(std::uint64_t frame_id, const dynamic::PairSet& pairs, cv::Size image,
                                   const std::vector<Detection>& predicted, DynamicOutcome& out) {
  AwaitBoxes(frame_id, pairs, image, out);
  // R12: in a frame the detector did not see (detector.stride, late), a track's
  // predicted box where no box of its class holds the mover. Where the detector
  // ran, its boxes and R10 decide: the predictions there too lost dyn_dev static
  // keypoints (18.6 -> 20.6 %) for no better ATE (docs/algorithm1.md, R12).
  if (out.fresh_boxes) return;
  for (const Detection& p : predicted) {
    const auto holds = [&](const Detection& d) {
      return d.carried == 0 && (d.class_name == p.class_name || p.class_name == movers::kUnknownClass) &&
             dynamic::BoxIou(d.box, p.box) >= kCarryIou;
    };
    if (std::any_of(out.detections.begin(), out.detections.end(), holds)) continue;
    out.detections.push_back(p);
    ++out.carried, ++out.predicted;
  }
}

void DynamicStage::AwaitBoxes(std::uint64_t frame_id, const dynamic::PairSet& pairs, cv::Size image,
                              DynamicOutcome& out) {
  if (!worker_) return;
  if (!submitted_) {  // between detector frames: the last boxes, moved with the flow
    out.followed = true;
    for (const Detection& d : last_boxes_) {
      if (const auto box = dynamic::FollowBox(d.box, pairs.cur, pairs.flow, image)) {
        out.detections.push_back(d);
        out.detections.back().box = *box;
      }
    }
  } else {
    const Stopwatch wait;
    auto result = worker_->WaitResult(frame_id, timeout_);
    out.wait_ms = wait.ElapsedMs();
    if (result) {
      out.detections = std::move(result->detections);
      out.detector_ms = result->inference_ms;
      out.fresh_boxes = true;
    } else {
      out.detector_late = true;  // carry on geometry-only for this frame
    }
  }
  last_boxes_ = out.detections;  // every frame: the stride factor may change at any frame
  // Late or not, the moving objects of the last frames are still about.
  std::vector<Detection> carried = carrier_.Carry(out.detections, pairs.cur, pairs.flow, image);
  out.carried = static_cast<int>(carried.size());
  out.detections.insert(out.detections.end(), carried.begin(), carried.end());
}

dynamic::RejectionResult DynamicStage::Judge(const dynamic::PairSet& pairs, const std::vector<cv::KeyPoint>& keys,
                                             const cv::Mat& depth_raw, cv::Size image, bool first,
                                             const std::vector<Detection>& detections) {
  // No flow yet in sg's first frame: the boxes are the only evidence (R11).
  const dynamic::Mode mode = first && mode_ == dynamic::Mode::kSg ? dynamic::Mode::kSemantic : mode_;
  std::optional<dynamic::DepthCheckInput> depth;
  if (config_.refinements.depth_check && !prev_depth_.empty()) depth = DepthInput(prev_depth_, depth_raw);
  std::vector<Detection> judged;
  const double max_area = kMaxBoxArea * image.area();  // R8
  for (const Detection& d : detections) {
    if (!config_.refinements.box_area_limit || d.box.area() <= max_area) judged.push_back(d);
  }
  if (first) first_boxes_ = judged;  // for JudgeFirstAgain (kept only when boxes_only_)
  return dynamic::JudgePairs(mode, pairs, keys, judged, Weight(), config_, depth ? &*depth : nullptr,
                             prior_.cell > 0 ? &prior_ : nullptr);
}

DynamicOutcome DynamicStage::Label(std::uint64_t frame_id, const cv::Mat& gray, const cv::Mat& depth_raw,
                                   const std::vector<cv::KeyPoint>& keys, const std::vector<Detection>& predicted) {
  DynamicOutcome out;
  out.dynamic.assign(keys.size(), 0);
  out.moving.assign(keys.size(), 0);
  if (mode_ == dynamic::Mode::kNone) return out;

  const Stopwatch flow_watch;
  const bool first = prev_.gray.empty();
  dynamic::FlowFrame cur{gray, {}};
  const dynamic::PairSet pairs = TrackFlow(keys, cur);
  const double flow_ms = flow_watch.ElapsedMs();
  AwaitDetections(frame_id, pairs, gray.size(), config_.refinements.track_footprints ? predicted : kNoBoxes, out);

  const Stopwatch watch;
  if (!first || mode_ == dynamic::Mode::kSemantic || mode_ == dynamic::Mode::kSg) {
    const dynamic::RejectionResult r = Judge(pairs, keys, depth_raw, gray.size(), first, out.detections);
    if (boxes_only_ && config_.refinements.first_frame_rejudge && mode_ == dynamic::Mode::kSg) {
      out.static_in_first = JudgeFirstAgain(cur, depth_raw, Weight());
    }
    out.unjudged.assign(keys.size(), 0);
    for (std::size_t i = 0; i < keys.size(); ++i) {
      out.dynamic[i] = r.keypoints[i].kept ? 0 : 1;
      out.unjudged[i] = r.keypoints[i].why == dynamic::Why::kUnjudged ? 1 : 0;
      const dynamic::KeypointVerdict& v = r.keypoints[i];
      out.moving[i] = v.why == dynamic::Why::kDepth || (std::isfinite(v.distance) && v.distance >= config_.eps_std);
    }
    out.kept = r.kept;
    out.rejected_geometry = r.rejected_geometry;
    out.rejected_semantics = r.rejected_semantics;
    out.rejected_depth = r.rejected_depth;
    out.judged = true;
    prior_ = dynamic::MakeDynamicPrior(keys, r, gray.size(), config_.refinements.prior_cells ? kPriorCell : 0,
                                       &prior_, kPriorMemory);
    if (worker_ && config_.refinements.box_carry) {
      const std::vector<Detection> own(out.detections.begin(), out.detections.end() - out.predicted);
      carrier_.Remember(own, ShowMotion(keys, r, own));
    }
  } else {
    out.kept = static_cast<int>(keys.size());
  }
  out.reject_ms = flow_ms + watch.ElapsedMs();
  boxes_only_ = first && mode_ == dynamic::Mode::kSg && worker_ != nullptr && config_.refinements.first_frame_rejudge;
  out.judged_again = boxes_only_;
  if (boxes_only_) {
    first_keys_ = keys;
  } else {
    first_keys_.clear(), first_boxes_.clear();
  }
  prev_ = std::move(cur);
  prev_depth_ = depth_raw;
  return out;
}

}  // namespace sgslam
