// A CPU budget for robots (config budget.cores): the cores the whole process may
// use at the camera's frame rate, the rest left to the robot's driver, planner and
// controller. Every kWindow frames the controller compares the process's CPU time
// with the camera time those frames span (so a dataset run as fast as frames load
// is judged at the rate it was recorded) and moves a throttle level: up one when
// the window used more than the budget, down one when it used less than
// kLower of it. The level lowers the rates of what can be skipped, cheapest loss
// first (SlamSystem applies it): the detector runs on every (stride x (level + 1))-th
// frame, and the semantic thread's keyframe model waits for a view change 2^level
// times larger. Tracking, local mapping and loop closing are never throttled:
// when the budget is below what they need the level stays at kMaxLevel and a
// warning says how many cores the run needs.
//
// Thread safety: none; driven from the tracking thread.
#pragma once

#include <optional>

#include "sgslam/common/time.h"

namespace sgslam {

class CpuBudget {
 public:
  static constexpr int kWindow = 30;      // frames between decisions (1 s of a 30 Hz camera)
  static constexpr int kMaxLevel = 4;     // detector every 5 x stride frames, keyframe model 16x the view change
  static constexpr double kLower = 0.7;   // a window under this share of the budget lowers the level

  // cores: the budget; <= 0 means none (Update never changes the level).
  explicit CpuBudget(double cores) : cores_(cores) {}

  // One frame: its camera time and the process's CPU seconds so far. Returns the
  // level after it (changed only at the end of a window).
  int Update(Timestamp t, double cpu_seconds);

  bool enabled() const { return cores_ > 0; }
  double cores() const { return cores_; }
  int level() const { return level_; }
  int max_level_reached() const { return max_level_; }
  int windows() const { return windows_; }
  int windows_over() const { return windows_over_; }  // windows that used more than the budget
  // The cores the last window used (CPU seconds over camera seconds); none before the first.
  std::optional<double> last_usage() const { return last_usage_; }

 private:
  double cores_;
  int level_ = 0, max_level_ = 0;
  int frames_ = 0, windows_ = 0, windows_over_ = 0;
  Timestamp window_t_ = 0;
  double window_cpu_ = 0;
  std::optional<double> last_usage_;
};

// The process's CPU time (user + system, every thread), in seconds.
double ProcessCpuSeconds();

}  // namespace sgslam
