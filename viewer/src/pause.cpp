#include "pause.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <cstdint>

#include "sgslam/common/error.h"

namespace sgslam::viewer {

PauseControl::PauseControl() : fd_(eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {
  if (fd_ < 0) throw Error("viewer: cannot make an eventfd for pause and step");
}

PauseControl::~PauseControl() { close(fd_); }

void PauseControl::Wake() {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = write(fd_, &one, sizeof one);  // a full counter is awake already
}

void PauseControl::Pause() { paused_ = true; }

void PauseControl::Resume() {
  paused_ = false;
  Wake();
}

void PauseControl::Step() {
  {
    std::lock_guard lock(mutex_);
    ++steps_;
  }
  paused_ = true;
  Wake();
}

bool PauseControl::MayGo() {
  std::uint64_t drained = 0;
  [[maybe_unused]] const ssize_t n = read(fd_, &drained, sizeof drained);
  std::lock_guard lock(mutex_);
  if (steps_ > 0) {
    --steps_;
    return true;
  }
  return !paused_;
}

}  // namespace sgslam::viewer
