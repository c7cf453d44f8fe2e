// The ground truth as the viewer draws it: moved into the run's world by the ATE's
// alignment (eval/ate.h) to the estimate, so the two lines can be compared.
#pragma once

#include <vector>

#include "sgslam/io/trajectory.h"

namespace sgslam::viewer {

// x y z of every ground-truth pose in the estimate's world; empty when fewer than
// three poses associate (then there is nothing to align with yet).
std::vector<float> AlignedTruth(const Trajectory& truth, const Trajectory& estimate);

}  // namespace sgslam::viewer
