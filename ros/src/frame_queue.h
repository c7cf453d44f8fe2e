// The frames between the ROS callbacks and the tracking thread: a bounded queue
// that, when full, drops its oldest frame (counted), so that a camera faster than
// the system costs frames, never memory, and the frame tracked next is a recent one.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>
#include <utility>

namespace sgslam::ros_bridge {

template <typename T>
class DropOldestQueue {
 public:
  explicit DropOldestQueue(std::size_t capacity) : capacity_(capacity > 0 ? capacity : 1) {}

  // Adds item; when the queue is full the oldest waiting item goes first. Ignored
  // once closed.
  void Push(T item) {
    {
      const std::lock_guard lock(mutex_);
      if (closed_) return;
      if (items_.size() == capacity_) {
        items_.pop_front();
        ++dropped_;
      }
      items_.push_back(std::move(item));
    }
    ready_.notify_one();
  }

  // The oldest item, waiting at most `wait` for one; nullopt on time-out or when
  // closed and empty (closed() tells which).
  std::optional<T> PopFor(std::chrono::milliseconds wait) {
    std::unique_lock lock(mutex_);
    ready_.wait_for(lock, wait, [&] { return closed_ || woken_ || !items_.empty(); });
    woken_ = false;
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    return item;
  }

  // No more items are taken; those waiting can still be popped.
  void Close() {
    {
      const std::lock_guard lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
  }
  // Ends the wait of a PopFor (for work other than items): it returns nullopt.
  void Wake() {
    {
      const std::lock_guard lock(mutex_);
      woken_ = true;
    }
    ready_.notify_all();
  }

  bool closed() const {
    const std::lock_guard lock(mutex_);
    return closed_;
  }
  std::size_t dropped() const {
    const std::lock_guard lock(mutex_);
    return dropped_;
  }
  std::size_t size() const {
    const std::lock_guard lock(mutex_);
    return items_.size();
  }

 private:
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<T> items_;
  std::size_t dropped_ = 0;
  bool closed_ = false;
  bool woken_ = false;
};

}  // namespace sgslam::ros_bridge
