#include "stop_signals.h"

namespace sgslam::app {

namespace {

std::atomic<int> g_signal{0};
std::atomic<bool> g_stop{false};
extern "C" void OnStopSignal(int signal) {
  g_signal = signal;
  g_stop = true;
}

}  // namespace

StopSignals::StopSignals() {
  g_signal = 0;
  g_stop = false;
  for (const int s : kSignals) previous_.push_back(std::signal(s, OnStopSignal));
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
