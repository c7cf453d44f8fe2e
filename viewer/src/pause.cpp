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

void PauseControl::Pause(Holder page) {
  std::lock_guard lock(mutex_);
  holders_.insert(page);
}

void PauseControl::Step(Holder page) {
  {
    std::lock_guard lock(mutex_);
    holders_.insert(page);
    ++steps_;
  }
  Wake();
}

void PauseControl::Unpause() {
  holders_.clear();
  steps_ = 0;  // a step left over would let a later pause through one frame
}

void PauseControl::Resume() {
  {
    std::lock_guard lock(mutex_);
    Unpause();
  }
  Wake();
}

bool PauseControl::Release(Holder page) {
  {
    std::lock_guard lock(mutex_);
    if (holders_.erase(page) == 0 || !holders_.empty()) return false;
    Unpause();
  }
  Wake();
  return true;
}

bool PauseControl::paused() const {
  std::lock_guard lock(mutex_);
  return !holders_.empty();
}

bool PauseControl::MayGo() {
  std::uint64_t drained = 0;
  [[maybe_unused]] const ssize_t n = read(fd_, &drained, sizeof drained);
  std::lock_guard lock(mutex_);
  if (holders_.empty()) return true;
  if (steps_ > 0) {
    --steps_;
    return true;
  }
  return false;
}

}  // namespace sgslam::viewer
