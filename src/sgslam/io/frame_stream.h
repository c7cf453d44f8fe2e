// Streams the frames of a dataset in order, reading a few ahead on a background
// thread so that image decoding overlaps with tracking. Never holds more than
// `prefetch` decoded frames. A read error is re-thrown by Next() in the consumer.
#pragma once

#include <cstddef>
#include <exception>
#include <optional>
#include <thread>

#include "sgslam/common/bounded_queue.h"
#include "sgslam/io/tum_dataset.h"

namespace sgslam {

class FrameStream {
 public:
  // Reads frames [0, max_frames) (all when max_frames == 0).
  FrameStream(const TumDataset& dataset, const CameraConfig& camera, std::size_t prefetch,
              std::size_t max_frames = 0);
  ~FrameStream();
  FrameStream(const FrameStream&) = delete;
  FrameStream& operator=(const FrameStream&) = delete;

  // The next frame, or nullopt at the end. Throws the reader's InputError.
  std::optional<RgbdImages> Next();
  std::size_t size() const { return count_; }

 private:
  struct Item {
    std::optional<RgbdImages> frame;
    std::exception_ptr error;
  };
  void ReadLoop();

  const TumDataset& dataset_;
  const CameraConfig camera_;
  const std::size_t count_;
  BoundedQueue<Item> queue_;
  std::thread reader_;
  bool finished_ = false;
};

}  // namespace sgslam
