// The object detection thread of the paper (Sec. III-A, Fig. 1): every RGB frame
// goes to the detector while tracking extracts ORB features and computes the
// fundamental matrix; tracking then waits for the detections of the same frame
// (with a timeout, so a late detector costs one frame's semantics, not a stall).
//
// Thread contract:
// - Submit() and Wait() are called by one producer/consumer thread (tracking);
//   Shutdown() and stats() by any thread. Frame ids must increase from Submit to
//   Submit.
// - The detector runs on a Stage (common/stage.h): the thread `sg-detector`, or
//   inline inside Submit in sequential mode, one frame at a time.
// - Submit never blocks on inference: at most max_pending frames wait behind the
//   one being processed in the stage's drop-oldest queue; a newer frame pushes out
//   the oldest waiting one, which is counted as dropped. The image passed to Submit is shared,
//   not copied: its pixels must not be written afterwards.
// - Wait(id) returns the frame's detections once ready; nullopt on timeout, when
//   the frame was dropped, never submitted, or after Shutdown(). Results of frames
//   up to id are then discarded, so memory stays bounded.
// - An exception thrown by the detector is rethrown by the next Wait() (once).
// - Sequential mode: deterministic results, the same Wait() semantics (it never
//   has to block).
// - Shutdown() wakes every waiter and drops the pending frames; the destructor
//   calls it and ends the stage. Waiting is on condition variables only.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "sgslam/common/stage.h"
#include "sgslam/detection/detector.h"

namespace sgslam {

struct DetectionResult {
  std::uint64_t frame_id = 0;
  Timestamp t = 0;
  std::vector<Detection> detections;
  double inference_ms = 0;  // time inside Detector::Detect
};

struct DetectionWorkerStats {
  std::uint64_t submitted = 0;
  std::uint64_t processed = 0;  // Detect returned (or threw)
  std::uint64_t dropped = 0;    // pushed out of the pending queue, or abandoned at Shutdown
  std::uint64_t timeouts = 0;   // Wait gave up before the frame was done
  std::uint64_t errors = 0;     // Detect threw
  double total_inference_ms = 0;
  double max_inference_ms = 0;
};

class DetectionWorker {
 public:
  struct Options {
    bool sequential = false;      // run the detector inside Submit (tests, evaluation)
    std::size_t max_pending = 1;  // frames waiting behind the one in progress
  };

  DetectionWorker(std::unique_ptr<Detector> detector, Options options);
  ~DetectionWorker();
  DetectionWorker(const DetectionWorker&) = delete;
  DetectionWorker& operator=(const DetectionWorker&) = delete;

  void Submit(std::uint64_t frame_id, Timestamp t, cv::Mat bgr);
  std::optional<std::vector<Detection>> Wait(std::uint64_t frame_id, std::chrono::milliseconds timeout);
  // Wait() with the frame's timing.
  std::optional<DetectionResult> WaitResult(std::uint64_t frame_id, std::chrono::milliseconds timeout);
  void Shutdown();

  DetectionWorkerStats stats() const;
  const std::string& Describe() const { return description_; }  // the detector's, taken at start

 private:
  struct Job {
    std::uint64_t frame_id;
    Timestamp t;
    cv::Mat bgr;
  };
  // A submitted frame's outcome: outstanding (queued or in progress) until it is
  // done or dropped.
  struct Slot {
    bool outstanding = true;
    std::optional<DetectionResult> result;
  };
  void Process(Job job);                   // runs Detect outside the lock, then stores the outcome
  void Dropped(std::uint64_t frame_id);    // needs mutex_
  void KeepResultsBounded();               // needs mutex_

  const std::unique_ptr<Detector> detector_;
  const Options options_;
  const std::string description_;
  mutable std::mutex mutex_;  // guards what follows, up to stage_
  std::condition_variable result_ready_;
  std::optional<std::uint64_t> last_submitted_;
  std::map<std::uint64_t, Slot> slots_;  // submitted frames not yet waited for
  std::exception_ptr error_;             // first detector exception not yet rethrown
  bool shut_down_ = false;
  DetectionWorkerStats stats_;
  Stage<Job> stage_;  // last: started after every other member exists, ended first
};

}  // namespace sgslam
