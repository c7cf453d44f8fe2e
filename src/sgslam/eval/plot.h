// Top view of an ATE result: ground truth in dark grey, the aligned estimate
// coloured by its per-pose ATE error, with a colour bar, a metric scale and the
// RMSE in the title. The view plane is spanned by the two principal axes of the
// ground-truth positions, so it suits any world frame (TUM's z-forward included).
#pragma once

#include <filesystem>

#include "sgslam/eval/ate.h"
#include "sgslam/io/trajectory.h"

namespace sgslam::eval {

struct AtePlotOptions {
  int width = 1000;  // px
  int height = 760;  // px
};

// Writes a PNG atomically. Throws InputError naming path when it cannot be written.
void WriteAtePlot(const std::filesystem::path& path, const Trajectory& gt, const Trajectory& est,
                  const AteResult& ate, const AtePlotOptions& options = {});

}  // namespace sgslam::eval
