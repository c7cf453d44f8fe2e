// Timing and resource figures recorded on every run (timing is always on).
#pragma once

#include <chrono>
#include <vector>

namespace sgslam {

// Wall-clock stopwatch in milliseconds.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double ElapsedMs() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }
  void Restart() { start_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

// Median (mean of the two middle values for an even count); 0 for an empty input.
double Median(std::vector<double> values);
// The q-quantile (0..1) by nearest rank, no interpolation; 0 for an empty input.
double Percentile(std::vector<double> values, double q);

// Peak resident set size of this process in MiB (VmHWM), 0 when unknown.
double PeakRssMiB();

// Resident set size of this process now in MiB (VmRSS), 0 when unknown.
double RssMiB();

}  // namespace sgslam
