#include "stop_signals.h"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <ctime>

namespace sgslam::app {

namespace {

std::atomic<int> g_signal{0};
std::atomic<bool> g_stop{false};
// The self-pipe that wakes WaitUntil: the handler writes a byte (write is
// async-signal-safe), the wait polls the read end. Created once, kept open.
int g_wake[2] = {-1, -1};

extern "C" void OnStopSignal(int signal) {
  g_signal = signal;
  g_stop = true;
  if (g_wake[1] >= 0) {
    const char byte = 1;
    [[maybe_unused]] const ssize_t n = write(g_wake[1], &byte, 1);  // a full pipe is awake already
  }
}

}  // namespace

StopSignals::StopSignals() {
  g_signal = 0;
  g_stop = false;
  if (g_wake[0] < 0 && pipe2(g_wake, O_CLOEXEC | O_NONBLOCK) != 0) g_wake[0] = g_wake[1] = -1;
  char drain[64];
  while (g_wake[0] >= 0 && read(g_wake[0], drain, sizeof drain) > 0) {
  }
  for (const int s : kSignals) previous_.push_back(std::signal(s, OnStopSignal));
}

bool StopSignals::WaitUntil(std::chrono::steady_clock::time_point deadline, int also_fd) {
  using std::chrono::steady_clock;
  while (!Received()) {
    const steady_clock::time_point now = steady_clock::now();
    if (now >= deadline) return true;
    auto left = std::chrono::duration_cast<std::chrono::nanoseconds>(deadline - now);
    if (g_wake[0] < 0) left = std::min<std::chrono::nanoseconds>(left, std::chrono::milliseconds(50));  // no pipe: slices
    const std::timespec timeout{static_cast<std::time_t>(left.count() / 1'000'000'000),
                                static_cast<long>(left.count() % 1'000'000'000)};
    pollfd wake[2] = {{g_wake[0], POLLIN, 0}, {also_fd, POLLIN, 0}};
    // Woken by the pipe, interrupted, or timed out: the loop tells which.
    if (ppoll(wake, also_fd >= 0 ? 2 : 1, &timeout, nullptr) > 0 && (wake[1].revents & POLLIN)) return !Received();
  }
  return false;
}

StopSignals::~StopSignals() {
  for (std::size_t i = 0; i < kSignals.size(); ++i) std::signal(kSignals[i], previous_[i]);
}

int StopSignals::Received() { return g_signal.load(); }
const std::atomic<bool>& StopSignals::Flag() { return g_stop; }

const char* SignalName(int signal) {
  return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : signal == SIGHUP ? "SIGHUP" : "a signal";
}

}  // namespace sgslam::app
