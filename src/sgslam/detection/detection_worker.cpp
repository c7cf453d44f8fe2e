#include "sgslam/detection/detection_worker.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "sgslam/common/stats.h"

namespace sgslam {

namespace {

// Outcomes nobody waits for (a consumer that skips Wait) are capped at this many.
constexpr std::size_t kMaxKeptResults = 16;
// wait_for adds the timeout to now(): keep the sum far from overflowing.
constexpr std::chrono::milliseconds kMaxTimeout = std::chrono::hours(24);

}  // namespace

DetectionWorker::DetectionWorker(std::unique_ptr<Detector> detector, Options options)
    : detector_(std::move(detector)),
      options_{options.sequential, std::max<std::size_t>(options.max_pending, 1)},
      description_(detector_ ? detector_->Describe() : ""),
      stage_("sg-detector", options_.max_pending, Overflow::kDropOldest) {
  if (!detector_) throw std::invalid_argument("DetectionWorker needs a detector");
  stage_.Start(!options_.sequential, [this](Job job) { Process(std::move(job)); });
}

DetectionWorker::~DetectionWorker() {
  Shutdown();
  stage_.Finish();
}

void DetectionWorker::Submit(std::uint64_t frame_id, Timestamp t, cv::Mat bgr) {
  {
    std::lock_guard lock(mutex_);
    if (last_submitted_ && frame_id <= *last_submitted_) {
      throw std::invalid_argument("DetectionWorker::Submit: frame id " + std::to_string(frame_id) + " after " +
                                  std::to_string(*last_submitted_) + "; ids must increase");
    }
    last_submitted_ = frame_id;
    ++stats_.submitted;
    if (shut_down_) {
      ++stats_.dropped;
      return;
    }
    slots_[frame_id];  // outstanding
  }
  auto pushed = stage_.Post(Job{frame_id, t, std::move(bgr)});  // sequential: processed now
  std::lock_guard lock(mutex_);
  if (!pushed.accepted) Dropped(frame_id);  // shut down meanwhile
  if (pushed.dropped) Dropped(pushed.dropped->frame_id);
}

void DetectionWorker::Dropped(std::uint64_t frame_id) {
  ++stats_.dropped;
  if (const auto it = slots_.find(frame_id); it != slots_.end()) it->second.outstanding = false;
  KeepResultsBounded();
  result_ready_.notify_all();  // its waiter, if any, sees it is no longer outstanding
}

void DetectionWorker::Process(Job job) {
  DetectionResult result{job.frame_id, job.t, {}, 0.0};
  std::exception_ptr error;
  const Stopwatch watch;
  try {
    result.detections = detector_->Detect(job.bgr, job.t);
  } catch (...) {
    error = std::current_exception();
  }
  result.inference_ms = watch.ElapsedMs();
  job.bgr.release();

  const bool failed = error != nullptr;
  std::lock_guard lock(mutex_);
  ++stats_.processed;
  stats_.total_inference_ms += result.inference_ms;
  stats_.max_inference_ms = std::max(stats_.max_inference_ms, result.inference_ms);
  if (error) {
    ++stats_.errors;
    // Moved (or dropped) under the lock: this thread keeps no reference, so the
    // exception dies in the thread that rethrows it (libstdc++ counts exception_ptr
    // references in code TSan does not see).
    if (!error_) error_ = std::move(error);  // the first one explains the rest
    error = nullptr;
  }
  // A frame whose slot is gone was waited past: its result is of no use.
  if (const auto it = slots_.find(job.frame_id); it != slots_.end()) {
    it->second.outstanding = false;
    if (!failed) it->second.result = std::move(result);
    KeepResultsBounded();
  }
  result_ready_.notify_all();
}

std::optional<std::vector<Detection>> DetectionWorker::Wait(std::uint64_t frame_id, std::chrono::milliseconds timeout) {
  auto result = WaitResult(frame_id, timeout);
  if (!result) return std::nullopt;
  return std::move(result->detections);
}

std::optional<DetectionResult> DetectionWorker::WaitResult(std::uint64_t frame_id, std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  const auto outstanding = [&] {
    const auto it = slots_.find(frame_id);
    return it != slots_.end() && it->second.outstanding;
  };
  const bool done = result_ready_.wait_for(lock, std::clamp(timeout, std::chrono::milliseconds(0), kMaxTimeout),
                                           [&] { return shut_down_ || error_ || !outstanding(); });
  std::optional<DetectionResult> out;
  if (const auto it = slots_.find(frame_id); it != slots_.end()) out = std::move(it->second.result);
  slots_.erase(slots_.begin(), slots_.upper_bound(frame_id));
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  if (!done) ++stats_.timeouts;
  return out;
}

void DetectionWorker::Shutdown() {
  {
    std::lock_guard lock(mutex_);
    if (shut_down_) return;
    shut_down_ = true;
  }
  const auto abandoned = stage_.Abandon();
  std::lock_guard lock(mutex_);
  for (const Job& job : abandoned) Dropped(job.frame_id);
  result_ready_.notify_all();
}

DetectionWorkerStats DetectionWorker::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void DetectionWorker::KeepResultsBounded() {
  std::size_t done = 0;
  for (const auto& [id, slot] : slots_) done += !slot.outstanding;
  for (auto it = slots_.begin(); done > kMaxKeptResults && it != slots_.end();) {
    if (it->second.outstanding) {
      ++it;
    } else {
      it = slots_.erase(it);
      --done;
    }
  }
}

}  // namespace sgslam
