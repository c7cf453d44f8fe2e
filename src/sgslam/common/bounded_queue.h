// The one bounded queue for passing messages between threads (docs/architecture.md,
// "Threads and queues"; Basalt's typed queues): a blocking pop, a Shutdown()
// that wakes every waiter, and what a full queue does with a new item:
//   kBlock       the producer waits for room (local mapping's keyframes, the reader);
//   kDropOldest  the oldest item is dropped and counted: a live system behind the
//                camera wants the newest data, stale items are worthless (detector,
//                the ROS node's frames).
// PopFor() and Wake() serve a consumer that also has other work (the ROS node's
// tracking thread: save requests between frames).
// No sleeps, no polling.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>

namespace sgslam {

enum class Overflow { kBlock, kDropOldest };

template <class T>
class BoundedQueue {
 public:
  explicit BoundedQueue(std::size_t capacity, Overflow overflow = Overflow::kBlock)
      : capacity_(capacity == 0 ? 1 : capacity), overflow_(overflow) {}

  struct Pushed {
    bool accepted = false;   // false after Shutdown(): the item was discarded
    std::optional<T> dropped;  // kDropOldest: the item pushed out to make room
  };
  // kBlock: blocks while full. kDropOldest: never blocks.
  Pushed Push(T item) {
    std::unique_lock lock(mutex_);
    if (overflow_ == Overflow::kBlock) {
      not_full_.wait(lock, [&] { return shut_down_ || items_.size() < capacity_; });
    }
    Pushed out;
    if (shut_down_) return out;
    if (items_.size() >= capacity_) {
      out.dropped = std::move(items_.front());
      items_.pop_front();
      ++dropped_;
    }
    items_.push_back(std::move(item));
    out.accepted = true;
    not_empty_.notify_one();
    return out;
  }

  // Pushes only into an empty queue (never blocks, never drops): false when an item
  // waits already, or after Shutdown().
  bool PushIfEmpty(T item) {
    std::lock_guard lock(mutex_);
    if (shut_down_ || !items_.empty()) return false;
    items_.push_back(std::move(item));
    not_empty_.notify_one();
    return true;
  }

  // Blocks while empty. Returns nullopt once shut down and drained.
  std::optional<T> Pop() {
    std::unique_lock lock(mutex_);
    not_empty_.wait(lock, [&] { return shut_down_ || !items_.empty(); });
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    not_full_.notify_one();
    return item;
  }

  // Pop() that waits at most `wait` and returns early, with nullopt, on Wake(); also
  // nullopt on time-out and once shut down and drained (shut_down() tells which).
  std::optional<T> PopFor(std::chrono::milliseconds wait) {
    std::unique_lock lock(mutex_);
    not_empty_.wait_for(lock, wait, [&] { return shut_down_ || woken_ || !items_.empty(); });
    woken_ = false;
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    not_full_.notify_one();
    return item;
  }

  // Ends the wait of a PopFor (the consumer has work other than items).
  void Wake() {
    std::lock_guard lock(mutex_);
    woken_ = true;
    not_empty_.notify_all();
  }

  // Items already queued can still be popped; pushes fail from now on.
  void Shutdown() {
    std::lock_guard lock(mutex_);
    shut_down_ = true;
    not_empty_.notify_all();
    not_full_.notify_all();
  }

  // Shutdown() that also takes every queued item out, at once: for a consumer that
  // abandons what is left (no item is popped after this returns).
  std::deque<T> ShutdownAndClear() {
    std::lock_guard lock(mutex_);
    shut_down_ = true;
    std::deque<T> out;
    out.swap(items_);
    not_empty_.notify_all();
    not_full_.notify_all();
    return out;
  }

  bool shut_down() const {
    std::lock_guard lock(mutex_);
    return shut_down_;
  }
  std::size_t size() const {
    std::lock_guard lock(mutex_);
    return items_.size();
  }
  std::size_t dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
  }

 private:
  const std::size_t capacity_;
  const Overflow overflow_;
  mutable std::mutex mutex_;
  std::condition_variable not_empty_, not_full_;
  std::deque<T> items_;
  std::size_t dropped_ = 0;
  bool shut_down_ = false;
  bool woken_ = false;
};

}  // namespace sgslam
