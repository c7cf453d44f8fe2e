// SIGINT (Ctrl-C), SIGTERM (timeout, systemd, docker, roslaunch) and SIGHUP (a
// closed terminal) for the long commands (run, synth): while a StopSignals lives,
// they only set a flag, so the command stops after the step it is on and keeps its
// work; the previous handlers come back on scope exit.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <csignal>
#include <vector>

namespace sgslam::app {

class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // The signal received since construction, or 0.
  static int Received();
  // Set when one was received (for code that polls a flag).
  static const std::atomic<bool>& Flag();
  // Waits until the deadline, or less when a stop signal arrives (the handler wakes
  // the wait through a pipe: no polling) or also_fd (when >= 0) becomes readable.
  // False when stopped by a signal.
  static bool WaitUntil(std::chrono::steady_clock::time_point deadline, int also_fd = -1);

 private:
  static constexpr std::array<int, 3> kSignals = {SIGINT, SIGTERM, SIGHUP};
  std::vector<void (*)(int)> previous_;
};

// "SIGINT", "SIGTERM", "SIGHUP", or "a signal".
const char* SignalName(int signal);

}  // namespace sgslam::app
