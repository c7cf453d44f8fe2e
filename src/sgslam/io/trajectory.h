// TUM trajectory files: "timestamp tx ty tz qx qy qz qw" per line, T_w_c.
#pragma once

#include <filesystem>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/common/time.h"

namespace sgslam {

struct StampedPose {
  Timestamp t = 0;
  SE3 T_w_c;
};
using Trajectory = std::vector<StampedPose>;

// Reads a TUM trajectory, sorted by time. Throws InputError for a missing file and
// ParseError (file:line) for a line without 8 numbers, or with a quaternion whose
// norm is zero or overflows.
Trajectory ReadTumTrajectory(const std::filesystem::path& path);

// Writes atomically; timestamps with 6 decimals, values with 9 significant digits.
void WriteTumTrajectory(const std::filesystem::path& path, const Trajectory& trajectory);

}  // namespace sgslam
