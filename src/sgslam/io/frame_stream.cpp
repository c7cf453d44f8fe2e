#include "sgslam/io/frame_stream.h"

#include <algorithm>

#include "sgslam/common/thread_name.h"

namespace sgslam {

FrameStream::FrameStream(const TumDataset& dataset, const CameraConfig& camera, std::size_t prefetch,
                         std::size_t max_frames)
    : dataset_(dataset),
      camera_(camera),
      count_(max_frames == 0 ? dataset.size() : std::min(max_frames, dataset.size())),
      queue_(prefetch) {
  reader_ = std::thread([this] {
    NameThisThread("sg-reader");
    ReadLoop();
  });
}

FrameStream::~FrameStream() {
  queue_.Shutdown();  // wakes the reader if it waits for room
  reader_.join();
}

void FrameStream::ReadLoop() {
  for (std::size_t i = 0; i < count_; ++i) {
    Item item;
    try {
      item.frame = dataset_.Load(i, camera_);
    } catch (...) {
      item.error = std::current_exception();
    }
    const bool failed = item.error != nullptr;
    if (!queue_.Push(std::move(item)).accepted || failed) break;
  }
  queue_.Shutdown();  // end of stream: the consumer drains what is queued
}

std::optional<RgbdImages> FrameStream::Next() {
  if (finished_) return std::nullopt;
  std::optional<Item> item = queue_.Pop();
  if (!item) {
    finished_ = true;
    return std::nullopt;
  }
  if (item->error) {
    finished_ = true;
    std::rethrow_exception(item->error);
  }
  return std::move(item->frame);
}

}  // namespace sgslam
