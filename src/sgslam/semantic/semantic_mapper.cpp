#include "sgslam/semantic/semantic_mapper.h"

#include <algorithm>
#include <utility>

#include <spdlog/spdlog.h>

#include "sgslam/camera/camera.h"
#include "sgslam/common/stats.h"
#include "sgslam/common/thread_name.h"
#include "sgslam/map/keyframe.h"

namespace sgslam {

namespace {

// The box window (box_window.h, semantic.filters.box_window): the frames on each
// side of a keyframe whose dynamic boxes are carried into its mask. A CPU detector
// misses a person in some frames; 2 frames took dyn_dev's cloud on movers from 1.7 %
// to 1.4 %, 4 frames to 1.2 % but with 11 % fewer points (and each keyframe
// waits for the frames after it).
constexpr int kBoxWindow = 2;  // frames
// A carried box grows by this per frame of distance
// (the mover's own motion), and is not carried at all when it covers more of the
// image.
constexpr double kBoxWindowGrowth = 4.0;   // px per frame
constexpr double kBoxWindowMaxArea = 0.5;  // share of the image
// Frames of boxes kept for a semantic thread that lags behind tracking.
constexpr std::size_t kBoxHistory = 600;

}  // namespace

SemanticMapper::SemanticMapper(const SemanticConfig& config, std::shared_ptr<const Camera> camera, ClassTable classes,
                               const Map& map, bool sequential, std::unique_ptr<Detector> keyframe_detector)
    : config_(config),
      camera_(camera),
      classes_(classes),
      map_(config, std::move(camera), std::move(classes), map, std::move(keyframe_detector)),
      stage_("sg-semantic", static_cast<std::size_t>(config.queue_size), Overflow::kDropOldest) {
  // Behind, the oldest keyframe goes: its views are the most covered by later ones.
  // The map is for later use, poses are for now: on two cores the semantic work
  // takes only the time tracking and local mapping leave (Linux: per-thread nice).
  stage_.Start(!sequential, [this](Job job) { Work(std::move(job)); }, [low = config.low_priority] {
    if (low) LowerThisThreadsPriority();
  });
}

SemanticMapper::~SemanticMapper() { Finish(); }

void SemanticMapper::Submit(SemanticInput input) {
  std::lock_guard lock(window_mutex_);
  if (finished_) return;
  pending_.push_back(std::move(input));
  Release(false);
}

void SemanticMapper::AddFrame(std::uint64_t frame_id, const SE3& T_c_w, const std::vector<Detection>& detections,
                              const cv::Mat& depth_raw) {
  if (!config_.filters.box_window) return;
  FrameBoxes f;
  f.frame_id = frame_id;
  f.T_c_w = T_c_w;
  for (const Detection& d : detections) {
    if (!classes_.is_dynamic(d.class_name)) continue;
    f.boxes.push_back(d);
    f.depth.push_back(BoxMedianDepth(depth_raw, camera_->config().depth_factor, d.box));
  }
  std::lock_guard lock(window_mutex_);
  frames_.push_back(std::move(f));
  while (frames_.size() > kBoxHistory) frames_.pop_front();
  last_frame_id_ = frame_id;
  Release(false);
}

bool SemanticMapper::WindowComplete(std::uint64_t keyframe_frame_id) const {
  const auto window = static_cast<std::uint64_t>(config_.filters.box_window ? kBoxWindow : 0);
  return window == 0 || (last_frame_id_ && *last_frame_id_ >= keyframe_frame_id + window);
}

std::vector<CarriedBox> SemanticMapper::CarriedBoxes(std::uint64_t keyframe_frame_id) const {
  std::vector<CarriedBox> out;
  if (!config_.filters.box_window) return out;
  const int window = kBoxWindow;
  const auto own = std::find_if(frames_.begin(), frames_.end(),
                                [&](const FrameBoxes& f) { return f.frame_id == keyframe_frame_id; });
  if (own == frames_.end()) return out;  // older than the history: its own boxes only
  const cv::Size image(camera_->width(), camera_->height());
  for (const FrameBoxes& f : frames_) {
    const auto distance = static_cast<double>(f.frame_id > keyframe_frame_id ? f.frame_id - keyframe_frame_id
                                                                             : keyframe_frame_id - f.frame_id);
    if (f.frame_id == keyframe_frame_id || distance > window || f.boxes.empty()) continue;
    const std::vector<CarriedBox> carried = CarryBoxes(f, own->T_c_w, *camera_, image,
                                                       kBoxWindowGrowth * distance,
                                                       kBoxWindowMaxArea);
    out.insert(out.end(), carried.begin(), carried.end());
  }
  return out;
}

void SemanticMapper::Release(bool all) {
  while (!pending_.empty() && (all || WindowComplete(pending_.front().keyframe->frame_id))) {
    Job job;
    job.carried = CarriedBoxes(pending_.front().keyframe->frame_id);
    job.keyframe = std::move(pending_.front());
    pending_.pop_front();
    const auto pushed = stage_.Post(std::move(job));
    if (pushed.dropped && pushed.dropped->keyframe) {  // not a wake-up (Wake)
      std::lock_guard lock(mutex_);
      ++stats_.dropped;
    }
  }
}

void SemanticMapper::Finish() {
  {
    std::lock_guard lock(window_mutex_);
    if (finished_) return;
    Release(true);  // the last keyframes' windows end with the sequence
    finished_ = true;
  }
  stage_.Finish();
  ServeRequests();  // those that came after the stage's last job
}

void SemanticMapper::Wake() {
  if (finished_) {
    ServeRequests();  // this thread is now the only one touching the map
  } else {
    stage_.PostIfEmpty(Job{});  // a job waiting already serves the requests first
  }
}

void SemanticMapper::RequestOctoMap(const std::filesystem::path& path) {
  {
    std::lock_guard lock(mutex_);
    octomap_request_ = path;
  }
  Wake();
}

void SemanticMapper::RequestState(std::function<void(SemanticState)> fn) {
  {
    std::lock_guard lock(mutex_);
    state_request_ = std::move(fn);
  }
  Wake();
}

std::size_t SemanticMapper::octomaps_written() const {
  std::lock_guard lock(mutex_);
  return octomaps_written_;
}

void SemanticMapper::Work(Job job) {
  ServeRequests();
  if (job.keyframe) ProcessKeyFrame(*job.keyframe, job.carried);
}

void SemanticMapper::ServeRequests() {
  std::unique_lock lock(mutex_);
  const bool rebuild = std::exchange(rebuild_pending_, false);
  const std::function<void(SemanticState)> state = std::exchange(state_request_, nullptr);
  const std::optional<std::filesystem::path> octomap = std::exchange(octomap_request_, std::nullopt);
  lock.unlock();
  if (rebuild) map_.RebuildOctoMap();
  if (state) state(map_.State());  // the clouds are this thread's
  if (octomap) WriteLiveOctoMap(*octomap);  // the OctoMap is this thread's
}

SemanticMapper::Published SemanticMapper::published() const {
  std::lock_guard lock(published_mutex_);
  return published_;
}

SemanticStats SemanticMapper::stats() const {
  std::lock_guard lock(mutex_);
  SemanticStats s = stats_;
  const auto median = [&](double SemanticMap::StageMs::*field) {
    std::vector<double> v;
    for (const SemanticMap::StageMs& m : stage_ms_) v.push_back(m.*field);
    return Median(std::move(v));
  };
  s.median_mask_ms = median(&SemanticMap::StageMs::mask);
  s.median_cloud_ms = median(&SemanticMap::StageMs::cloud);
  s.median_octomap_ms = median(&SemanticMap::StageMs::octomap);
  std::vector<double> detect;
  for (const SemanticMap::StageMs& m : stage_ms_) {
    if (m.model_ran) detect.push_back(m.detect);
  }
  s.model_keyframes = detect.size();
  s.median_detect_ms = Median(std::move(detect));
  s.median_objects_ms = median(&SemanticMap::StageMs::objects);
  return s;
}

void SemanticMapper::Restore(SemanticState state) {
  map_.Restore(std::move(state));
  {  // threaded, the stage builds it before its first keyframe: loading a map does not wait for it
    std::lock_guard lock(mutex_);
    rebuild_pending_ = true;
  }
  Wake();
}

void SemanticMapper::WriteLiveOctoMap(const std::filesystem::path& path) {
  try {
    map_.WriteOctoMap(path);
    spdlog::info("OctoMap so far ({} keyframes) written to {}", map_.keyframes(), path.string());
    std::lock_guard lock(mutex_);
    ++octomaps_written_;
  } catch (const std::exception& e) {
    spdlog::error("OctoMap request: {}", e.what());
  }
}

void SemanticMapper::ProcessKeyFrame(const SemanticInput& input, const std::vector<CarriedBox>& carried) {
  const Stopwatch total;
  const SemanticMap::StageMs ms = map_.Add(input, carried);
  if (publishing_) {
    SemanticMap::Snapshot latest = map_.Latest();
    std::lock_guard lock(published_mutex_);
    published_.clouds.emplace_back(std::move(latest.keyframe), std::move(latest.cloud));
    published_.objects = std::move(latest.objects);
    published_.cells = std::move(latest.cells);
  }
  std::lock_guard lock(mutex_);
  ++stats_.keyframes;
  stats_.ms.push_back(total.ElapsedMs());
  stage_ms_.push_back(ms);
}

void SemanticMapper::ExportCloud(std::vector<Eigen::Vector3d>& points, std::vector<Rgb>& colours) {
  const std::size_t freed = map_.ExportCloud(points, colours);
  std::lock_guard lock(mutex_);
  stats_.cloud_points = points.size();
  stats_.cloud_points_freed = freed;
}

}  // namespace sgslam
