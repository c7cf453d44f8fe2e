#include "sgslam/semantic/semantic_mapper.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>

#include <spdlog/spdlog.h>

#include "sgslam/camera/camera.h"
#include "sgslam/common/stats.h"
#include "sgslam/common/thread_name.h"
#include "sgslam/map/keyframe.h"

namespace sgslam {

namespace {

// The box window (box_window.h): a carried box grows by this per frame of distance
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
      sequential_(sequential),
      camera_(camera),
      classes_(classes),
      map_(config, std::move(camera), std::move(classes), map, std::move(keyframe_detector)) {
  if (!sequential_) {
    thread_ = std::thread([this] {
      NameThisThread("sg-semantic");
      Loop();
    });
  }
}

SemanticMapper::~SemanticMapper() { Finish(); }

void SemanticMapper::Submit(SemanticInput input) {
  if (sequential_) {
    queue_.push_back(std::move(input));
    ProcessReady(false);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    if (stop_) return;
    if (queue_.size() >= static_cast<std::size_t>(config_.queue_size)) {
      queue_.pop_front();  // behind: the oldest keyframe's views are the most covered by later ones
      ++stats_.dropped;
    }
    queue_.push_back(std::move(input));
  }
  wake_.notify_one();
}

void SemanticMapper::AddFrame(std::uint64_t frame_id, const SE3& T_c_w, const std::vector<Detection>& detections,
                              const cv::Mat& depth_raw) {
  if (config_.box_window <= 0) return;
  FrameBoxes f;
  f.frame_id = frame_id;
  f.T_c_w = T_c_w;
  for (const Detection& d : detections) {
    if (!classes_.is_dynamic(d.class_name)) continue;
    f.boxes.push_back(d);
    f.depth.push_back(BoxMedianDepth(depth_raw, camera_->config().depth_factor, d.box));
  }
  {
    std::lock_guard lock(mutex_);
    frames_.push_back(std::move(f));
    while (frames_.size() > kBoxHistory) frames_.pop_front();
    last_frame_id_ = frame_id;
  }
  if (sequential_) {
    ProcessReady(false);
  } else {
    wake_.notify_one();
  }
}

bool SemanticMapper::WindowComplete(std::uint64_t keyframe_frame_id) const {
  const auto window = static_cast<std::uint64_t>(std::max(0, config_.box_window));
  return window == 0 || (last_frame_id_ && *last_frame_id_ >= keyframe_frame_id + window);
}

std::vector<CarriedBox> SemanticMapper::CarriedBoxes(std::uint64_t keyframe_frame_id) const {
  std::vector<CarriedBox> out;
  const int window = config_.box_window;
  if (window <= 0) return out;
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

void SemanticMapper::ProcessReady(bool all) {
  while (!queue_.empty() && (all || WindowComplete(queue_.front().keyframe->frame_id))) {
    const SemanticInput input = std::move(queue_.front());
    queue_.pop_front();
    ProcessKeyFrame(input, CarriedBoxes(input.keyframe->frame_id));
  }
}

void SemanticMapper::Finish() {
  if (finished_) return;
  finished_ = true;
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (sequential_) ProcessReady(true);  // the last keyframes' windows end with the sequence
}

void SemanticMapper::RequestOctoMap(const std::filesystem::path& path) {
  if (sequential_ || finished_) {  // this thread is the only one touching the OctoMap
    WriteLiveOctoMap(path);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    octomap_request_ = path;
  }
  wake_.notify_one();
}

void SemanticMapper::RequestState(std::function<void(SemanticState)> fn) {
  if (sequential_ || finished_) {  // this thread is the only one touching the clouds
    fn(map_.State());
    return;
  }
  {
    std::lock_guard lock(mutex_);
    state_request_ = std::move(fn);
  }
  wake_.notify_one();
}

std::size_t SemanticMapper::octomaps_written() const {
  std::lock_guard lock(mutex_);
  return octomaps_written_;
}

void SemanticMapper::Loop() {
  // The map is for later use; poses are for now: on two cores the semantic work
  // takes only the time tracking and local mapping leave (Linux: per-thread nice).
  if (config_.low_priority) setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 19);
  for (;;) {
    SemanticInput input;
    std::vector<CarriedBox> carried;
    {
      std::unique_lock lock(mutex_);
      // The front keyframe waits for the frames after it (box_window), so that it
      // is masked with the same boxes as in sequential mode.
      wake_.wait(lock, [&] {
        return stop_ || octomap_request_ || state_request_ || rebuild_pending_ ||
               (!queue_.empty() && WindowComplete(queue_.front().keyframe->frame_id));
      });
      if (rebuild_pending_) {
        rebuild_pending_ = false;
        lock.unlock();
        map_.RebuildOctoMap();
        continue;
      }
      if (state_request_) {
        const auto fn = std::move(state_request_);
        state_request_ = nullptr;
        lock.unlock();
        fn(map_.State());  // the clouds are this thread's
        continue;
      }
      if (octomap_request_) {
        const std::filesystem::path path = *octomap_request_;
        octomap_request_.reset();
        lock.unlock();
        WriteLiveOctoMap(path);  // the OctoMap is this thread's
        continue;
      }
      if (queue_.empty()) return;  // stopped and drained
      input = std::move(queue_.front());
      queue_.pop_front();
      carried = CarriedBoxes(input.keyframe->frame_id);
    }
    ProcessKeyFrame(input, carried);
  }
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
  if (map_.has_keyframe_detector()) s.median_detect_ms = median(&SemanticMap::StageMs::detect);
  s.median_objects_ms = median(&SemanticMap::StageMs::objects);
  return s;
}

void SemanticMapper::Restore(SemanticState state) {
  map_.Restore(std::move(state));
  if (sequential_) {
    map_.RebuildOctoMap();
    return;
  }
  {  // the worker builds it before its first keyframe: loading a map does not wait for it
    std::lock_guard lock(mutex_);
    rebuild_pending_ = true;
  }
  wake_.notify_one();
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
