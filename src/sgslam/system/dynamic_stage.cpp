#include "sgslam/system/dynamic_stage.h"

#include <spdlog/spdlog.h>

#include "sgslam/camera/camera.h"
#include "sgslam/common/stats.h"

namespace sgslam {

DynamicStage::DynamicStage(const Config& config, std::unique_ptr<Detector> detector, bool sequential)
    : config_(config),
      mode_(dynamic::ParseMode(config.dynamic.mode)),
      wants_detector_(mode_ == dynamic::Mode::kSemantic || mode_ == dynamic::Mode::kSg),
      camera_(std::make_shared<Camera>(config.camera)),
      classes_(config.detector) {
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

DetectionWorkerStats DynamicStage::detector_stats() const { return worker_ ? worker_->stats() : DetectionWorkerStats{}; }

DynamicOutcome DynamicStage::Label(std::uint64_t frame_id, const cv::Mat& gray, const cv::Mat& depth_raw,
                                   const std::vector<cv::KeyPoint>& keys, const std::optional<SE3>& T_cur_prev) {
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
      pairs = dynamic::TrackPairs(prev_, cur, keys, config_.dynamic, undistort);
    }
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
    const bool pnp = dyn.depth_motion == "pnp";
    if (dyn.depth_check && (pnp || T_cur_prev) && !prev_depth_.empty()) {
      depth.emplace();
      depth->prev_depth = prev_depth_;
      depth->cur_depth = depth_raw;
      depth->depth_factor = config_.camera.depth_factor;
      depth->K = {camera_->fx(), camera_->fy(), camera_->cx(), camera_->cy()};
      if (T_cur_prev) depth->T_cur_prev = *T_cur_prev;  // pnp: replaced by the PnP estimate
    }
    const dynamic::RejectionResult r = dynamic::JudgePairs(pairs, keys, out.detections, weight, dyn,
                                                           depth ? &*depth : nullptr, prior_.cell > 0 ? &prior_ : nullptr);
    for (std::size_t i = 0; i < keys.size(); ++i) out.dynamic[i] = r.keypoints[i].kept ? 0 : 1;
    out.kept = r.kept;
    out.rejected_geometry = r.rejected_geometry;
    out.rejected_semantics = r.rejected_semantics;
    out.rejected_depth = r.rejected_depth;
    out.judged = true;
    prior_ = dynamic::MakeDynamicPrior(keys, r, gray.size(), config_.dynamic.prior_cell);
  } else {
    out.kept = static_cast<int>(keys.size());
  }
  out.reject_ms = flow_ms + watch.ElapsedMs();
  prev_ = std::move(cur);
  prev_depth_ = depth_raw;
  return out;
}

}  // namespace sgslam
