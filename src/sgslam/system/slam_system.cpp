#include "sgslam/system/slam_system.h"

#include <algorithm>
#include <filesystem>
#include <thread>


#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <shared_mutex>
#include <spdlog/spdlog.h>

#include "sgslam/common/stats.h"
#include "sgslam/detection/darknet_model.h"
#include "sgslam/detection/dnn_detector.h"
#include "sgslam/loop/vocabulary_file.h"
#include "sgslam/map/map_check.h"

namespace sgslam {

namespace {

constexpr std::size_t kLoopQueueSize = 16;  // keyframes waiting for loop detection (a few ms each)
constexpr int kGlobalBaIterations = 10;     // per stage, after a loop (ORB-SLAM2)
constexpr std::size_t kMappingQueueSize = 3;  // keyframes waiting for local mapping, beyond which tracking waits
// Frames after a keyframe during which local mapping counts as busy for the
// keyframe decision (ORB-SLAM2's "idle" rule). --sequential steps the mapper at
// once, so it always waits this long; in parallel, a keyframe due later
// interrupts a running BA, as ORB-SLAM2's InterruptBA does.
constexpr std::uint64_t kMappingBusyFrames = 5;

// The semantic thread's second, larger detector (semantic.keyframe_model): only
// where tracking's runs on the network backend (file detections are exact already;
// without a detector no mode uses boxes). Missing model files: a warning, none.
std::unique_ptr<Detector> MakeKeyFrameDetector(const Config& config, bool tracking_has_detector) {
  if (config.semantic.keyframe_model.empty() || config.detector.backend != "dnn" || !tracking_has_detector) {
    return nullptr;
  }
  DetectorConfig dc = config.detector;
  dc.model = config.semantic.keyframe_model;
  const std::filesystem::path dir = ResolveModelDir(dc.model_dir);
  if (!DarknetModelPresent(dir, dc.model)) {
    spdlog::warn("semantic.keyframe_model {}: no {}.cfg and .weights in {}; the map masks movers with tracking's "
                 "boxes alone (set semantic.keyframe_model to \"\" to silence this)",
                 dc.model, dc.model, dir.string());
    return nullptr;
  }
  return std::make_unique<DnnDetector>(dc);  // a broken file is an error, as for tracking's
}

}  // namespace

SlamSystem::SlamSystem(const Config& config, bool sequential, std::unique_ptr<Detector> detector)
    : config_(config),
      sequential_(sequential),
      camera_(std::make_shared<Camera>(config.camera)),
      scale_(std::make_shared<ScaleLevels>(features::MakeScaleLevels(config.orb.scale_factor, config.orb.levels))),
      extractor_(config.orb),
      dynamic_(config.dynamic, config.detector, camera_, std::move(detector), sequential),
      places_(MakeKeyFrameDatabase(config.loop)),
      tracker_(config.tracking, config.orb.features, config.camera, map_, places_),
      mapper_(config.mapping, config.camera.close_depth_m(), map_, places_),
      budget_(config.budget.cores),
      mapping_("sg-mapping", kMappingQueueSize),
      loops_("sg-loop", kLoopQueueSize) {
  // orb.threads 0: a helper thread only where a core is free for it; on two
  // cores local mapping has the second one.
  const bool spare_core = std::thread::hardware_concurrency() > 2 && !sequential_ && !dynamic_.has_detector();
  extractor_.set_threads(config.orb.threads > 0 ? config.orb.threads : (spare_core ? 2 : 1));
  if (config.semantic.enabled) {
    semantic_ = std::make_unique<SemanticMapper>(config.semantic, camera_, ClassTable(config.detector), map_,
                                                 sequential, MakeKeyFrameDetector(config, dynamic_.has_detector()));
  }
  if (places_) loop_ = std::make_unique<LoopCloser>(map_, places_);
  tracker_.SetMoverBoxes([classes = ClassTable(config.detector)](const Detection& d) {
    return d.carried > 0 || d.class_name == movers::kUnknownClass || classes.is_dynamic(d.class_name);
  });
  if (dynamic_.mode() != dynamic::Mode::kNone) {
    movers_ = std::make_unique<movers::MoverTracker>(camera_, ClassTable(config.detector));
  }
  // Local mapping's BA stops for a keyframe that waits (parallel only).
  mapping_.Start(!sequential_, [this](SemanticInput item) {
    MapKeyFrame(std::move(item), [this] { return mapping_.queued() > 0; });
  });
  if (loop_) loops_.Start(!sequential_, [this](std::shared_ptr<KeyFrame> kf) { CloseLoops(kf); });
}

// Destroyed without Finish() (an error unwinding the run): stop the threads, but
// do not spend seconds refining a map nobody will export.
SlamSystem::~SlamSystem() { Stop(/*final_ba=*/false); }

void SlamSystem::Finish() { Stop(/*final_ba=*/true); }

void SlamSystem::HandOver(SemanticInput item) { mapping_.Post(std::move(item)); }

void SlamSystem::MapKeyFrame(SemanticInput item, const std::function<bool()>& interrupted) {
  MappingStats stats;
  {
    std::lock_guard step(mapping_step_mutex_);
    stats = mapper_.Process(item.keyframe, interrupted);
  }
  {
    std::lock_guard lock(stats_mutex_);
    mapping_stats_.push_back(stats);
  }
  const std::shared_ptr<KeyFrame> kf = item.keyframe;
  ToSemantic(std::move(item));
  if (loop_) loops_.Post(kf);
}

void SlamSystem::CloseLoops(const std::shared_ptr<KeyFrame>& kf) {
  LoopReport report;
  if (const std::optional<VerifiedLoop> loop = loop_->Detect(kf, report)) {
    const bool was_running = StopGlobalBa(/*abort=*/true);  // the last loop's: this one changes the map under it
    {
      std::lock_guard step(mapping_step_mutex_);  // local mapping waits (its BA must not undo the correction)
      loop_->Correct(*loop, report);
    }
    if (report.closed || was_running) StartGlobalBa();
  }
  if (report.closed) {
    spdlog::info("loop closed: frame {} (keyframe {}) sees frame {} (keyframe {}) again, {} inliers; moved {:.3f} m, "
                 "{:.2f} deg; {} keyframes in the pose graph, {:.0f} ms",
                 report.frame, report.keyframe, report.loop_frame, report.loop_keyframe, report.inliers,
                 report.correction_m, report.correction_deg, report.corrected_keyframes, report.correct_ms);
  }
  std::lock_guard lock(stats_mutex_);
  loop_reports_.push_back(report);
}

void SlamSystem::StartGlobalBa() {
  gba_abort_ = false;
  if (!global_ba_.Run(!sequential_, [this] { RunGlobalBa(); })) {
    spdlog::warn("no thread for the global bundle adjustment: it ran on the loop closing thread");
  }
}

void SlamSystem::RunGlobalBa() {
  const GlobalBaResult r = SolveGlobalBa(map_, kGlobalBaIterations, [this] { return gba_abort_.load(); });
  bool applied = false;
  if (!r.aborted && !r.T_c_w.empty()) {
    std::lock_guard step(mapping_step_mutex_);
    std::unique_lock lock(map_.mutex());
    if (!gba_abort_) ApplyGlobalBa(map_, r), applied = true;
  }
  if (applied) spdlog::info("global bundle adjustment after the loop: {} keyframes, {} points, {:.0f} ms", r.keyframes, r.points, r.ms);
  std::lock_guard lock(stats_mutex_);
  gba_reports_.push_back({r.keyframes, r.points, r.ms, !applied});
}

bool SlamSystem::StopGlobalBa(bool abort) {
  if (abort) gba_abort_ = true;
  return global_ba_.Join();
}

std::vector<SlamSystem::GlobalBaReport> SlamSystem::global_ba_reports() const {
  std::lock_guard lock(stats_mutex_);
  return gba_reports_;
}

std::vector<LoopReport> SlamSystem::loop_reports() const {
  std::lock_guard lock(stats_mutex_);
  return loop_reports_;
}

void SlamSystem::Stop(bool final_ba) {
  if (finished_) return;
  finished_ = true;
  // The last frame's keyframe waits for a frame that will not come.
  if (held_ && final_ba) HandOver(std::move(*held_));
  held_.reset();
  mapping_.Finish();  // what is queued is mapped first
  loops_.Finish();    // after local mapping: nothing feeds it any more
  // The final BA supersedes a running global BA; without one, it is waited for.
  // None in localisation mode: the frames stay in the map they were localised in.
  const bool run_final_ba = final_ba && config_.mapping.final_ba_iterations > 0 && !localization_only();
  StopGlobalBa(/*abort=*/!final_ba || run_final_ba);
  // With every keyframe mapped, one bundle adjustment of the whole map (what
  // ORB-SLAM2 runs after a loop closure). The trajectory is exported relative to
  // the keyframes, so it follows; so do the semantic cloud and objects.
  if (run_final_ba) final_ba_ = mapper_.GlobalBundleAdjustment();
  if (semantic_) semantic_->Finish();  // after local mapping: nothing feeds it any more
  std::lock_guard lock(save_mutex_);  // a save in flight ends (the semantic thread has served every request)
  saver_.Join();
}

void SlamSystem::ToSemantic(SemanticInput item) {
  if (!semantic_) return;
  bool bad = false;
  {
    std::shared_lock lock(map_.mutex());
    bad = item.keyframe->bad();  // culled as redundant: its views are in other keyframes
  }
  if (!bad) semantic_->Submit(std::move(item));
}

FrameReport SlamSystem::Process(const RgbdImages& images) {
  const Stopwatch total;
  FrameReport report;
  report.index = images.index;
  report.t = images.t;
  const std::uint64_t frame_id = next_frame_id_++;
  dynamic_.Submit(frame_id, images.t, images.bgr);  // the detector works on it while ORB runs (Fig. 1)
  std::vector<Detection> predicted;  // the mover tracks' boxes in this frame (R12)
  const Stopwatch movers_watch;
  if (movers_ && config_.dynamic.refinements.track_footprints) {
    if (const std::optional<SE3> T_c_w = tracker_.PredictedPose()) predicted = movers_->Footprints(*T_c_w, images.t);
  }
  report.movers_ms = movers_watch.ElapsedMs();
  Frame frame = MakeFrame(frame_id, images, predicted, report);
  const TrackResult result = Track(frame, report);
  RecordPoses(frame, result);
  if (movers_) UpdateMovers(frame, result, images, report);
  HandOverKeyFrames(frame, result, images, report);
  // After the keyframe's hand-over: in sequential mode this may complete its box
  // window. Every frame counts towards the window (a lost stretch must not hold
  // keyframes back); a lost frame's boxes are not carried, its pose is unknown.
  if (semantic_) {
    static const std::vector<Detection> kNone;
    const bool tracked = HasPose(result.state);
    semantic_->AddFrame(frame.id, frame.T_c_w, tracked ? frame.features->detections : kNone, images.depth);
  }
  NoteMapSize(report);
  ApplyBudget(images.t, report);
  report.rss_mib = RssMiB();
  report.total_ms = total.ElapsedMs();
  if (snapshots_) PublishFrame(frame, images, report);
  return report;
}

void SlamSystem::ApplyBudget(Timestamp t, FrameReport& report) {
  if (!budget_.enabled()) return;
  const int before = budget_.level(), windows = budget_.windows();
  const int level = budget_.Update(t, ProcessCpuSeconds());
  report.budget_level = level;
  if (level != before) {
    dynamic_.SetStrideFactor(level + 1);
    if (semantic_) semantic_->SetModelLevel(level);
    spdlog::debug("CPU budget: {:.2f} cores used over {}, throttle level {} -> {}", budget_.last_usage().value_or(0),
                  budget_.cores(), before, level);
  }
  // A whole window at the top level over the budget: nothing left to lower.
  if (budget_.windows() > windows && before == CpuBudget::kMaxLevel && !budget_warned_ &&
      budget_.last_usage().value_or(0) > budget_.cores()) {
    budget_warned_ = true;
    spdlog::warn("budget.cores {}: the run needs {:.2f} cores at the camera's rate with the detector and the keyframe "
                 "model at their lowest rates; tracking and mapping are not throttled",
                 budget_.cores(), *budget_.last_usage());
  }
}

void SlamSystem::NoteMapSize(FrameReport& report) {
  std::size_t held = 0;
  {
    std::shared_lock lock(map_.mutex());
    report.map_keyframes = static_cast<int>(map_.keyframes().size());
    report.map_points = static_cast<int>(map_.map_points().size());
    held = map_.keyframes().size() + map_.pending().size();
  }
  const int bound = config_.mapping.max_keyframes;
  if (bound > 0 && !map_full_at_ && held >= static_cast<std::size_t>(bound)) {
    spdlog::warn("the map holds {} keyframes (mapping.max_keyframes): it stops growing, and frames are tracked in it",
                 held);
    map_full_at_ = report.index;
    tracker_.SetLocalizationOnly(true);
  }
}

void SlamSystem::UpdateMovers(const Frame& frame, const TrackResult& result, const RgbdImages& images,
                              FrameReport& report) {
  const Stopwatch watch;
  const bool recorded = !records_.empty() && records_.back().frame_id == frame.id;
  if (!HasPose(result.state) || !recorded || moving_.size() != frame.size()) {
    movers_->Skip(frame.t);
    report.movers_ms += watch.ElapsedMs();
    return;
  }
  movers::FrameInput in;
  in.t = frame.t;
  in.T_c_w = frame.T_c_w;
  in.keys = &frame.features->keys;
  in.depth = &frame.features->depth;
  in.moving = &moving_;
  in.boxes = &frame.features->detections;
  in.fresh_boxes = fresh_boxes_;
  in.depth_raw = images.depth;
  movers_->Update(in);
  const Eigen::Matrix3d R_c_w = frame.T_c_w.rotation();
  for (const movers::Track& tr : movers_->tracks()) {
    track_samples_.push_back({records_.size() - 1, tr.id, tr.class_name, frame.T_c_w * tr.PositionAt(frame.t),
                              R_c_w * tr.velocity, tr.extent, tr.state});
    report.movers += tr.state == movers::TrackState::kConfirmed ? 1 : 0;
  }
  report.movers_ms += watch.ElapsedMs();
}

std::vector<movers::TrackLine> SlamSystem::MoverTracks() const {
  std::shared_lock lock(map_.mutex());
  std::vector<movers::TrackLine> out;
  out.reserve(track_samples_.size());
  for (const TrackSample& s : track_samples_) {
    const PoseRecord& r = records_[s.record];
    const SE3 T_w_c = (r.T_c_r * r.reference->PlacedT_c_w()).Inverse();
    out.push_back({r.t, s.id, s.class_name, T_w_c * s.p_c, T_w_c.rotation() * s.v_c, s.extent, s.state});
  }
  return out;
}

Frame SlamSystem::MakeFrame(std::uint64_t frame_id, const RgbdImages& images, const std::vector<Detection>& predicted,
                            FrameReport& report) {
  const Stopwatch watch;
  cv::Mat gray;
  cv::cvtColor(images.bgr, gray, cv::COLOR_BGR2GRAY);
  std::vector<cv::KeyPoint> keys;
  cv::Mat descriptors;
  extractor_.Extract(gray, keys, descriptors);
  report.extract_ms = watch.ElapsedMs();

  DynamicOutcome dyn = dynamic_.Label(frame_id, gray, images.depth, keys, predicted);  // Algorithm 1
  report.kept = dyn.judged ? dyn.kept : static_cast<int>(keys.size());
  report.rejected_geometry = dyn.rejected_geometry;
  report.rejected_semantics = dyn.rejected_semantics;
  report.rejected_depth = dyn.rejected_depth;
  const int boxes = static_cast<int>(dyn.detections.size()) - dyn.carried;
  report.detections = dyn.followed ? 0 : boxes;
  report.followed = dyn.followed ? boxes : 0;
  report.carried = dyn.carried - dyn.predicted;
  report.predicted = dyn.predicted;
  moving_ = std::move(dyn.moving);
  fresh_boxes_ = dyn.fresh_boxes;
  if (!dyn.followed) report.boxes.assign(dyn.detections.begin(), dyn.detections.end() - dyn.carried);
  report.detector_late = dyn.detector_late;
  report.detector_ms = dyn.detector_ms;
  report.wait_ms = dyn.wait_ms;
  report.reject_ms = dyn.reject_ms;
  if (!dyn.judged) dyn.dynamic.clear(), dyn.unjudged.clear();
  Frame frame(frame_id, images.t,
              MakeFeatures(std::move(keys), std::move(descriptors), images.depth, camera_, scale_,
                           std::move(dyn.dynamic), std::move(dyn.detections), std::move(dyn.unjudged),
                           tracker_.PredictedAngularVelocity().value_or(Eigen::Vector3d::Zero())));
  frame.judged_again = dyn.judged_again;
  report.features = static_cast<int>(frame.size());
  report.keypoints.reserve(frame.size());
  for (const auto& k : frame.features->keys) report.keypoints.push_back(k.pt);
  report.rejected = frame.rejected;
  if (!dyn.static_in_first.empty()) {
    // The first keyframe was judged by its boxes alone; judged again with this frame.
    const int cleared = tracker_.ConfirmStaticInFirstKeyFrame(dyn.static_in_first);
    if (cleared > 0) {
      spdlog::info("first keyframe: {} keypoints its boxes rejected are static, judged with the next frame", cleared);
    }
  }
  return frame;
}

TrackResult SlamSystem::Track(Frame& frame, FrameReport& report) {
  const Stopwatch watch;
  // Local mapping counts as idle kMappingBusyFrames after the last keyframe; in
  // parallel also whenever it really is idle.
  // A keyframe queued while its BA runs interrupts it (the mapper's interrupted()).
  const bool waited = frame.id >= last_keyframe_frame_id_ + kMappingBusyFrames;
  const bool idle = mapping_.threaded() ? mapping_.queued() == 0 && (!mapping_.busy() || waited) : waited;
  const bool full = mapping_.queued() >= kMappingQueueSize;
  const TrackResult result = tracker_.Track(frame, idle, full);
  report.state = result.state;
  report.matches = result.matches;
  report.inliers = result.inliers;
  report.trusted = result.trusted;
  report.track_ms = watch.ElapsedMs();
  return result;
}

void SlamSystem::RecordPoses(const Frame& frame, const TrackResult& result) {
  if (result.previous_refined && !records_.empty() && records_.back().frame_id == result.previous_refined->frame_id) {
    // The previous frame, fitted again with the velocity of the frames on either
    // side of it: its exported pose (relative to the same reference keyframe).
    std::shared_lock lock(map_.mutex());
    PoseRecord& r = records_.back();
    r.T_c_r = result.previous_refined->T_c_w * r.reference->T_w_c();
  }
  if (HasPose(result.state) && result.reference) {
    records_.push_back({frame.id, frame.t, result.reference, result.T_c_r, frame.T_c_w.Inverse()});
  }
}

void SlamSystem::HandOverKeyFrames(const Frame& frame, const TrackResult& result, const RgbdImages& images,
                                   FrameReport& report) {
  // The last frame's keyframe, held for this frame (TrackResult::keyframe_held).
  if (held_) {
    HandOver(std::move(*held_));
    held_.reset();
  }
  if (!result.new_keyframe) return;
  report.keyframe = true;
  last_keyframe_frame_id_ = frame.id;
  SemanticInput item{result.new_keyframe, images.bgr, images.depth};
  if (result.keyframe_held) {
    held_ = std::move(item);
  } else {
    HandOver(std::move(item));
  }
}

Trajectory SlamSystem::FrameTrajectory() const {
  std::shared_lock lock(map_.mutex());
  Trajectory out;
  out.reserve(records_.size());
  for (const auto& r : records_) {
    if (r.reference) out.push_back({r.t, (r.T_c_r * r.reference->PlacedT_c_w()).Inverse()});
  }
  return out;
}

Trajectory SlamSystem::OnlineTrajectory() const {
  Trajectory out;
  out.reserve(records_.size());
  for (const auto& r : records_) out.push_back({r.t, r.T_w_c_online});
  return out;
}

Trajectory SlamSystem::KeyFrameTrajectory() const {
  std::shared_lock lock(map_.mutex());
  Trajectory out;
  for (const auto& [id, kf] : map_.keyframes()) out.push_back({kf->t, kf->T_w_c()});
  return out;
}

std::vector<Eigen::Vector3d> SlamSystem::MapPointPositions() const {
  std::shared_lock lock(map_.mutex());
  std::vector<Eigen::Vector3d> out;
  out.reserve(map_.map_points().size());
  for (const auto& [id, p] : map_.map_points()) {
    if (!p->bad()) out.push_back(p->position());
  }
  return out;
}

std::size_t SlamSystem::NumKeyFrames() const {
  std::shared_lock lock(map_.mutex());
  return map_.keyframes().size();
}

std::vector<std::string> SlamSystem::CheckMap() const {
  std::shared_lock lock(map_.mutex());
  return CheckMapConsistency(map_);
}

void SlamSystem::ExportSemantic(std::vector<Eigen::Vector3d>& cloud, std::vector<Rgb>& colours,
                                std::vector<ObjectEstimate>& objects, const SE3& T_out_map) const {
  cloud.clear();
  colours.clear();
  objects.clear();
  if (!semantic_) return;
  std::shared_lock lock(map_.mutex());
  semantic_->ExportCloud(cloud, colours);
  objects = semantic_->ExportObjects(T_out_map);
}

std::vector<ObjectEstimate> SlamSystem::ExportObjects(const SE3& T_out_map) const {
  if (!semantic_) return {};
  std::shared_lock lock(map_.mutex());
  return semantic_->ExportObjects(T_out_map);
}

void SlamSystem::EnableSnapshots() {
  snapshots_ = true;
  if (semantic_) semantic_->EnablePublishing();
}

void SlamSystem::PublishFrame(const Frame& frame, const RgbdImages& images, const FrameReport& report) {
  auto s = std::make_shared<FrameSnapshot>();
  s->index = report.index;
  s->t = report.t;
  s->state = report.state;
  if (HasPose(report.state)) s->T_w_c = frame.T_c_w.Inverse();
  s->bgr = images.bgr;
  s->keypoints = report.keypoints;
  s->labels.resize(frame.size(), FrameSnapshot::kKept);
  const std::vector<std::uint8_t>& unjudged = frame.features->unjudged;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    if (frame.rejected[i]) {
      s->labels[i] = FrameSnapshot::kRejected;
    } else if (i < unjudged.size() && unjudged[i]) {
      s->labels[i] = FrameSnapshot::kUnjudged;
    }
  }
  s->detections = frame.features->detections;
  if (movers_ && HasPose(report.state)) {
    for (const movers::Track& tr : movers_->tracks()) {
      s->movers.push_back({tr.id, tr.class_name, tr.state, tr.PositionAt(frame.t), tr.velocity, tr.extent});
    }
  }
  s->keyframe = report.keyframe;
  s->frame_ms = report.total_ms;
  std::lock_guard lock(frame_snapshot_mutex_);
  latest_frame_ = std::move(s);
}

std::shared_ptr<const FrameSnapshot> SlamSystem::LatestFrame() const {
  std::lock_guard lock(frame_snapshot_mutex_);
  return latest_frame_;
}

MapSnapshot SlamSystem::SnapshotMap() const {
  MapSnapshot out;
  SemanticMapper::Published semantic;
  if (semantic_ && snapshots_) semantic = semantic_->published();  // before the map lock: never both held
  out.objects = std::move(semantic.objects);
  out.cells = std::move(semantic.cells);
  std::shared_lock lock(map_.mutex());
  for (const auto& [id, kf] : map_.keyframes()) out.keyframes.push_back({id, kf->t, kf->T_w_c()});
  out.points.reserve(map_.map_points().size());
  for (const auto& [id, p] : map_.map_points()) {
    if (!p->bad()) out.points.push_back(p->position());
  }
  for (auto& [kf, points] : semantic.clouds) {
    out.cloud.push_back({kf->id, kf->PlacedT_c_w().Inverse(), std::move(points)});
  }
  return out;
}

std::vector<MappingStats> SlamSystem::mapping_stats() const {
  std::lock_guard lock(stats_mutex_);
  return mapping_stats_;
}

}  // namespace sgslam
