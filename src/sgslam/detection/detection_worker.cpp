#include "sgslam/detection/detection_worker.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "sgslam/common/stats.h"

namespace sgslam {

namespace {

// Results nobody waits for (a consumer that skips Wait) are capped at this many.
constexpr std::size_t kMaxKeptResults = 16;
// wait_for adds the timeout to now(): keep the sum far from overflowing.
constexpr std::chrono::milliseconds kMaxTimeout = std::chrono::hours(24);

}  // namespace

DetectionWorker::DetectionWorker(std::unique_ptr<Detector> detector, Options options)
    : detector_(std::move(detector)),
      options_{options.sequential, std::max<std::size_t>(options.max_pending, 1)},
      description_(detector_ ? detector_->Describe() : "") {
  if (!detector_) throw std::invalid_argument("DetectionWorker needs a detector");
  if (!options_.sequential) thread_ = std::thread([this] { Run(); });
}

DetectionWorker::~DetectionWorker() {
  Shutdown();
  if (thread_.joinable()) thread_.join();
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
    if (!options_.sequential) {
      if (pending_.size() >= options_.max_pending) {
        pending_.pop_front();  // its waiter, if any, sees it is no longer outstanding
        ++stats_.dropped;
        result_ready_.notify_all();
      }
      pending_.push_back(Job{frame_id, t, std::move(bgr)});
      work_ready_.notify_one();
      return;
    }
    in_progress_ = frame_id;
  }
  Process(Job{frame_id, t, std::move(bgr)});
}

void DetectionWorker::Run() {
  for (;;) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      work_ready_.wait(lock, [&] { return shut_down_ || !pending_.empty(); });
      if (shut_down_) return;
      job = std::move(pending_.front());
      pending_.pop_front();
      in_progress_ = job.frame_id;
    }
    Process(std::move(job));
  }
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

  std::lock_guard lock(mutex_);
  in_progress_.reset();
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
  } else if (!last_waited_ || job.frame_id > *last_waited_) {
    results_.emplace(job.frame_id, std::move(result));
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
  const bool done = result_ready_.wait_for(lock, std::clamp(timeout, std::chrono::milliseconds(0), kMaxTimeout),
                                           [&] { return shut_down_ || error_ || !Outstanding(frame_id); });
  std::optional<DetectionResult> out;
  if (const auto it = results_.find(frame_id); it != results_.end()) out = std::move(it->second);
  results_.erase(results_.begin(), results_.upper_bound(frame_id));
  last_waited_ = std::max(last_waited_.value_or(0), frame_id);
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  if (!done) ++stats_.timeouts;
  return out;
}

void DetectionWorker::Shutdown() {
  std::lock_guard lock(mutex_);
  if (shut_down_) return;
  shut_down_ = true;
  stats_.dropped += pending_.size();
  pending_.clear();
  work_ready_.notify_all();
  result_ready_.notify_all();
}

DetectionWorkerStats DetectionWorker::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

bool DetectionWorker::Outstanding(std::uint64_t frame_id) const {
  if (in_progress_ == frame_id) return true;
  return std::any_of(pending_.begin(), pending_.end(), [&](const Job& j) { return j.frame_id == frame_id; });
}

void DetectionWorker::KeepResultsBounded() {
  while (results_.size() > kMaxKeptResults) results_.erase(results_.begin());
}

}  // namespace sgslam
