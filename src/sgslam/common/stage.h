// How the system runs its stages (docs/architecture.md, "Threads and queues"):
// a stage that consumes items (the detector's images, local mapping's keyframes,
// loop closing's, the semantic map's) runs
// either inline, on the thread that posts them (--sequential: the same bytes on
// every run), or on a named thread of its own behind a BoundedQueue. The stage's
// code is the same in both; only Stage knows which it is. Job is the same for
// one-off work (a global bundle adjustment, a map save).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <system_error>
#include <thread>
#include <utility>

#include "sgslam/common/bounded_queue.h"
#include "sgslam/common/thread_name.h"

namespace sgslam {

template <class T>
class Stage {
 public:
  using Work = std::function<void(T)>;

  Stage(std::string name, std::size_t capacity, Overflow overflow = Overflow::kBlock)
      : name_(std::move(name)), queue_(capacity, overflow) {}
  ~Stage() { Finish(); }
  Stage(const Stage&) = delete;
  Stage& operator=(const Stage&) = delete;

  // Once, before the first Post: inline, or a thread named `name` that works
  // through the queue until Finish(); on_thread: run first on that thread (its
  // priority, say).
  void Start(bool threaded, Work work, std::function<void()> on_thread = {}) {
    work_ = std::move(work);
    if (!threaded) return;
    thread_ = std::thread([this, on_thread = std::move(on_thread)] {
      NameThisThread(name_.c_str());
      if (on_thread) on_thread();
      while (auto item = queue_.Pop()) {
        busy_ = true;
        work_(std::move(*item));
        busy_ = false;
      }
    });
  }

  // Inline: the work runs now, on this thread. Threaded: the item is queued (a full
  // queue blocks or drops its oldest, as constructed: the result names the item
  // dropped). Ignored (not accepted) after Finish() or Abandon().
  typename BoundedQueue<T>::Pushed Post(T item) {
    typename BoundedQueue<T>::Pushed out;
    if (thread_.joinable()) {
      out = queue_.Push(std::move(item));
    } else if (work_ && !finished_) {
      work_(std::move(item));
      out.accepted = true;
    }
    return out;
  }

  // Post() only when no item waits (inline: always): a wake-up that must not push
  // an item out of a full drop-oldest queue. False when one waits, or after Finish().
  bool PostIfEmpty(T item) {
    if (thread_.joinable()) return queue_.PushIfEmpty(std::move(item));
    if (!work_ || finished_) return false;
    work_(std::move(item));
    return true;
  }

  // From any thread: the queued items are taken out and returned (not worked on),
  // the item in progress ends as usual, and nothing is accepted from now on.
  // Finish() still joins the thread.
  std::deque<T> Abandon() { return queue_.ShutdownAndClear(); }

  // The queued items are worked through, then the thread ends. Idempotent.
  void Finish() {
    finished_ = true;
    queue_.Shutdown();
    if (thread_.joinable()) thread_.join();
  }

  bool threaded() const { return thread_.joinable(); }
  std::size_t queued() const { return queue_.size(); }  // items waiting; 0 inline
  bool busy() const { return busy_; }                  // the thread is on an item; false inline

 private:
  const std::string name_;
  BoundedQueue<T> queue_;
  Work work_;
  std::atomic<bool> busy_{false};
  bool finished_ = false;  // the posting thread's
  std::thread thread_;
};

// One-off work at a time: inline, or on a thread named `name`.
class Job {
 public:
  explicit Job(std::string name) : name_(std::move(name)) {}
  ~Job() { Join(); }
  Job(const Job&) = delete;
  Job& operator=(const Job&) = delete;

  // Waits for the previous job, then runs fn: now on this thread, or on a thread of
  // its own. Returns false when fn ran here although a thread was asked for (none
  // could be started).
  bool Run(bool threaded, std::function<void()> fn) {
    Join();
    if (!threaded) {
      fn();
      return true;
    }
    const auto job = std::make_shared<std::function<void()>>(std::move(fn));  // still here if no thread starts
    try {
      thread_ = std::thread([this, job] {
        NameThisThread(name_.c_str());
        (*job)();
      });
    } catch (const std::system_error&) {
      (*job)();
      return false;
    }
    return true;
  }

  // Waits for the job on its thread; true when there was one (it may have ended).
  bool Join() {
    if (!thread_.joinable()) return false;
    thread_.join();
    return true;
  }

 private:
  const std::string name_;
  std::thread thread_;
};

}  // namespace sgslam
