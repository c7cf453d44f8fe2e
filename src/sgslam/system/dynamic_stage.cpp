#include "sgslam/system/dynamic_stage.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "sgslam/camera/camera.h"
#include "sgslam/common/stats.h"
#include "sgslam/dynamic/neighbours.h"
#include "sgslam/dynamic/rolling_pairs.h"

namespace sgslam {

DynamicStage::DynamicStage(const Config& config, std::unique_ptr<Detector> detector, bool sequential)
    : config_(config),
      mode_(dynamic::ParseMode(config.dynamic.mode)),
      wants_detector_(mode_ == dynamic::Mode::kSemantic || mode_ == dynamic::Mode::kSg),
      camera_(std::make_shared<Camera>(config.camera)),
      classes_(config.detector),
      carrier_(config.dynamic.carry_frames, config.dynamic.carry_iou,
               [table = ClassTable(config.detector)](const std::string& name) { return table.is_dynamic(name); }) {
  if (camera_->has_distortion() && config.dynamic.undistort_pairs && mode_ != dynamic::Mode::kNone &&
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
    spdlog::warn("mode {} without a detector: {}", config.dynamic.mode,
                 mode_ == dynamic::Mode::kSg ? "the epipolar test alone decides (as --mode geometric)"
                                             : "nothing is rejected (as --mode none)");
  }
}

std::string DynamicStage::DescribeDetector() const { return worker_ ? worker_->Describe() : "none"; }

void DynamicStage::Submit(std::uint64_t frame_id, Timestamp t, const cv::Mat& bgr) {
  if (worker_) worker_->Submit(frame_id, t, bgr);
}

void DynamicStage::ApplyTruthMask(const cv::Mat& mask, const std::vector<cv::KeyPoint>& keys, DynamicOutcome& out) {
  out.dynamic.assign(keys.size(), 0);
  out.unjudged.clear();  // the masks judge every keypoint
  out.kept = 0;
  out.rejected_geometry = out.rejected_depth = out.rejected_track = 0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    // The pixel eval::ScoreKeypoints scores the keypoint by.
    const int x = std::clamp(cvRound(keys[i].pt.x), 0, mask.cols - 1);
    const int y = std::clamp(cvRound(keys[i].pt.y), 0, mask.rows - 1);
    out.dynamic[i] = mask.at<std::uint8_t>(y, x) != 0 ? 1 : 0;
    out.kept += out.dynamic[i] == 0;
  }
  out.rejected_semantics = static_cast<int>(keys.size()) - out.kept;
  out.judged = true;
}

DetectionWorkerStats DynamicStage::detector_stats() const { return worker_ ? worker_->stats() : DetectionWorkerStats{}; }

int DynamicStage::ApplyMultiFrameChecks(const std::vector<cv::KeyPoint>& keys,
                                        const std::vector<dynamic::TrackVerdict>& tracks,
                                        dynamic::RejectionResult& r) {
  const DynamicConfig& c = config_.dynamic;
  // The fallback's minimum stays kept: the most moving-looking go first.
  const int min_kept = static_cast<int>(std::ceil(c.min_kept_ratio * static_cast<double>(keys.size())));
  int budget = std::max(0, r.kept - min_kept);
  const auto reject = [&](std::vector<std::size_t> idx, const std::function<double(std::size_t)>& score) {
    if (static_cast<int>(idx.size()) > budget) {
      std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return score(a) > score(b); });
      idx.resize(static_cast<std::size_t>(budget));
    }
    for (std::size_t i : idx) r.keypoints[i].kept = false, r.keypoints[i].why = dynamic::Why::kDepth;
    budget -= static_cast<int>(idx.size());
    return static_cast<int>(idx.size());
  };
  int rejected = 0;
  if (c.track_check && tracks.size() == keys.size()) {
    std::vector<std::size_t> moving;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (tracks[i].moving && r.keypoints[i].kept) moving.push_back(i);
    }
    rejected += reject(moving, [&](std::size_t i) { return tracks[i].residual; });
  }
  if (c.track_rescue && tracks.size() == keys.size()) {
    // Inside a dynamic box (w > 1) a static point is rejected at d >= eps_std / w
    // (0.6 px at w = 5: most of the static points in a person box on fr1); a track
    // that has stayed on its anchor for several frames is static whatever its box.
    int restored = 0;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      dynamic::KeypointVerdict& v = r.keypoints[i];
      if (v.kept || v.why != dynamic::Why::kGeometry || v.weight <= 1.0) continue;
      if (tracks[i].age < c.track_min_age || tracks[i].moving || tracks[i].residual > c.track_rescue_tolerance) continue;
      v.kept = true, v.why = dynamic::Why::kFallback;
      ++restored;
    }
    r.kept += restored, r.rejected_geometry -= restored, budget += restored;
  }
  if (c.unjudged_radius > 0) {
    rejected += reject(dynamic::UnjudgedAmongMovers(keys, r.keypoints, c.unjudged_radius, c.unjudged_share, 2),
                       [](std::size_t) { return 0.0; });
  }
  return rejected;
}

std::vector<bool> DynamicStage::ShowMotion(const std::vector<cv::KeyPoint>& keys, const dynamic::RejectionResult& r,
                                           const std::vector<Detection>& boxes) const {
  // Semantic mode has no geometry to ask, so it carries nothing: carrying every box
  // there rejected so much that dyn_dev kept only 78 of 300 frames tracked.
  if (mode_ == dynamic::Mode::kSemantic) return std::vector<bool>(boxes.size(), false);
  constexpr int kMinKeypoints = 5;  // fewer in a box: no verdict, not carried
  const DynamicConfig& c = config_.dynamic;
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
    moving[b] = inside >= kMinKeypoints && evidence >= c.carry_min_motion * inside;
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
  dynamic::UndistortPointsFn undistort;
  if (undistort_) undistort = [table = undistort_](std::vector<cv::Point2f>& p) { table->Apply(p); };
  const dynamic::PairSet pairs = dynamic::TrackPairs(cur, prev_, first_keys_, config_.dynamic, undistort);
  dynamic::DepthCheckInput depth;
  depth.prev_depth = depth_raw;
  depth.cur_depth = prev_depth_;
  depth.depth_factor = config_.camera.depth_factor;
  depth.K = {camera_->fx(), camera_->fy(), camera_->cx(), camera_->cy()};
  const dynamic::RejectionResult r = dynamic::JudgePairs(pairs, first_keys_, first_boxes_, weight, config_.dynamic,
                                                         config_.dynamic.depth_check ? &depth : nullptr);
  for (std::size_t i = 0; i < first_keys_.size(); ++i) {
    now_static[i] = r.keypoints[i].kept && r.keypoints[i].why == dynamic::Why::kStatic;
  }
  return now_static;
}

DynamicOutcome DynamicStage::Label(std::uint64_t frame_id, const cv::Mat& gray, const cv::Mat& depth_raw,
                                   const std::vector<cv::KeyPoint>& keys, const std::optional<SE3>& T_cur_prev,
                                   const std::optional<TurnRates>& turn) {
  DynamicOutcome out;
  out.dynamic.assign(keys.size(), 0);
  out.detector_used = worker_ != nullptr;
  if (mode_ == dynamic::Mode::kNone) return out;

  // Lines 1-2 (pyramid, backward LK, pair filters, undistortion) need no boxes:
  // they run while the detector works on the same frame, and tracking waits only
  // for what is left (paper Fig. 1).
  const Stopwatch flow_watch;
  dynamic::FlowFrame cur{gray, {}};
  const bool first = prev_.gray.empty();
  dynamic::PairSet pairs;
  if (mode_ != dynamic::Mode::kSemantic) {
    cur.pyramid = dynamic::BuildFlowPyramid(gray, config_.dynamic);
    if (!first) {
      dynamic::UndistortPointsFn undistort;
      if (undistort_) undistort = [table = undistort_](std::vector<cv::Point2f>& p) { table->Apply(p); };
      std::optional<dynamic::FlowPrediction> predict;
      if (T_cur_prev && config_.dynamic.lk_predict) {
        predict = dynamic::FlowPrediction{depth_raw, config_.camera.depth_factor,
                                          {camera_->fx(), camera_->fy(), camera_->cx(), camera_->cy()}, *T_cur_prev};
      }
      pairs = dynamic::TrackPairs(prev_, cur, keys, config_.dynamic, undistort, predict ? &*predict : nullptr);
    }
  }
  // The keypoint tracks need no boxes either (track_memory.h).
  std::vector<dynamic::TrackVerdict> tracks;
  const DynamicConfig& dc = config_.dynamic;
  const bool use_tracks = mode_ != dynamic::Mode::kSemantic && (dc.track_check || dc.track_rescue || dc.track_motion);
  if (use_tracks) {
    const dynamic::Pinhole K{camera_->fx(), camera_->fy(), camera_->cx(), camera_->cy()};
    tracks = tracks_.Update(keys, pairs.cur_un, pairs.flow, pairs.prev_un, depth_raw, config_.camera.depth_factor, K,
                            T_cur_prev, config_.dynamic);
  }
  const double flow_ms = flow_watch.ElapsedMs();

  if (worker_) {
    const Stopwatch wait;
    auto result = worker_->WaitResult(frame_id, std::chrono::milliseconds(config_.detector.timeout_ms));
    out.wait_ms = wait.ElapsedMs();
    if (result) {
      out.detections = std::move(result->detections);
      out.detector_ms = result->inference_ms;
    } else {
      out.detector_late = true;  // carry on geometry-only for this frame
    }
    // Late or not, the moving objects of the last frames are still about.
    std::vector<Detection> carried = carrier_.Carry(out.detections, pairs.cur, pairs.flow, gray.size());
    out.carried = static_cast<int>(carried.size());
    out.detections.insert(out.detections.end(), carried.begin(), carried.end());
  }

  const Stopwatch watch;
  // Algorithm 1 weighs a point by the largest w of the boxes holding it (a chair's
  // w = 2 too); semantic mode removes only the boxes of moving-object classes.
  dynamic::WeightFn weight;
  if (mode_ == dynamic::Mode::kSemantic) {
    weight = [this](const std::string& name) { return classes_.is_dynamic(name) ? classes_.weight(name) : 1.0; };
  } else {
    weight = [this](const std::string& name) { return classes_.weight(name); };
  }

  DynamicConfig dyn = config_.dynamic;
  if (first && mode_ == dynamic::Mode::kSg) dyn.mode = "semantic";  // no flow yet: boxes are the only evidence
  if (!first || mode_ == dynamic::Mode::kSemantic || mode_ == dynamic::Mode::kSg) {
    std::optional<dynamic::DepthCheckInput> depth;
    // The anchors' motion replaces the two-frame PnP of the RGB-D check (see track_memory.h).
    const bool from_tracks = use_tracks && tracks_.motion_from_tracks() && config_.dynamic.track_motion;
    if (from_tracks) dyn.depth_motion = "tracker";
    const bool pnp = dyn.depth_motion == "pnp";
    if (dyn.depth_check && (pnp || from_tracks || T_cur_prev) && !prev_depth_.empty()) {
      depth.emplace();
      depth->prev_depth = prev_depth_;
      depth->cur_depth = depth_raw;
      depth->depth_factor = config_.camera.depth_factor;
      depth->K = {camera_->fx(), camera_->fy(), camera_->cx(), camera_->cy()};
      if (from_tracks) depth->T_cur_prev = *tracks_.motion();
      else if (T_cur_prev) depth->T_cur_prev = *T_cur_prev;  // pnp: replaced by the PnP estimate
    }
    std::vector<Detection> judged;
    const double max_area = config_.dynamic.max_box_area * gray.cols * gray.rows;
    for (const Detection& d : out.detections) {
      if (d.box.area() <= max_area) judged.push_back(d);
    }
    if (first) first_boxes_ = judged;  // for JudgeFirstAgain (kept only when boxes_only_)
    std::optional<dynamic::RollingShutterInput> rolling;
    if (turn && config_.dynamic.rolling_shutter_pairs && config_.camera.readout > 0 && !first) {
      rolling.emplace();
      rolling->readout = config_.camera.readout;
      rolling->height = gray.rows;
      rolling->w_prev = turn->previous;
      rolling->w_guess = turn->predicted;
      rolling->prev_depth = prev_depth_;
      rolling->depth_factor = config_.camera.depth_factor;
      rolling->K = {camera_->fx(), camera_->fy(), camera_->cx(), camera_->cy()};
    }
    dynamic::RejectionResult r =
        dynamic::JudgePairs(pairs, keys, judged, weight, dyn, depth ? &*depth : nullptr,
                            prior_.cell > 0 ? &prior_ : nullptr, rolling ? &*rolling : nullptr);
    out.angular_velocity = r.angular_velocity;
    if (dc.forward_check > 0 && mode_ != dynamic::Mode::kSemantic && !first) {
      // Only the keypoints the flow alone condemns (outside the boxes) are checked.
      std::vector<std::size_t> which;
      std::vector<cv::Point2f> from, to;
      for (std::size_t i = 0; i < keys.size(); ++i) {
        const dynamic::KeypointVerdict& v = r.keypoints[i];
        if (v.kept || v.weight > 1.0 || pairs.flow.status[i] != dynamic::PairStatus::kOk) continue;
        if (v.why != dynamic::Why::kDepth && v.why != dynamic::Why::kGeometry) continue;
        which.push_back(i), from.push_back(pairs.flow.prev[i]), to.push_back(pairs.cur[i]);
      }
      const std::vector<bool> ok = dynamic::ForwardConsistent(prev_, cur, from, to, dc, dc.forward_check);
      for (std::size_t k = 0; k < which.size(); ++k) {
        if (ok[k]) continue;
        dynamic::KeypointVerdict& v = r.keypoints[which[k]];
        (v.why == dynamic::Why::kDepth ? r.rejected_depth : r.rejected_geometry) -= 1;
        v.kept = true, v.why = dynamic::Why::kUnjudged;
        ++r.kept;
      }
    }
    if (mode_ != dynamic::Mode::kSemantic) {
      out.rejected_track = ApplyMultiFrameChecks(keys, tracks, r);
      r.kept -= out.rejected_track;
      r.rejected_depth += out.rejected_track;
    }
    if (boxes_only_ && dc.first_frame_rejudge && mode_ == dynamic::Mode::kSg) {
      out.static_in_first = JudgeFirstAgain(cur, depth_raw, weight);
    }
    out.unjudged.assign(keys.size(), 0);
    for (std::size_t i = 0; i < keys.size(); ++i) {
      out.dynamic[i] = r.keypoints[i].kept ? 0 : 1;
      out.unjudged[i] = r.keypoints[i].why == dynamic::Why::kUnjudged ? 1 : 0;
    }
    out.kept = r.kept;
    out.rejected_geometry = r.rejected_geometry;
    out.rejected_semantics = r.rejected_semantics;
    out.rejected_depth = r.rejected_depth;
    out.judged = true;
    prior_ = dynamic::MakeDynamicPrior(keys, r, gray.size(), config_.dynamic.prior_cell, &prior_,
                                       config_.dynamic.prior_memory);
    if (worker_ && config_.dynamic.carry_frames > 0) carrier_.Remember(out.detections, ShowMotion(keys, r, out.detections));
  } else {
    out.kept = static_cast<int>(keys.size());
  }
  out.reject_ms = flow_ms + watch.ElapsedMs();
  boxes_only_ = first && mode_ == dynamic::Mode::kSg && worker_ != nullptr && config_.dynamic.first_frame_rejudge;
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
