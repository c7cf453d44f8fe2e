#include "truth.h"

#include "sgslam/common/error.h"
#include "sgslam/eval/ate.h"

namespace sgslam::viewer {

std::vector<float> AlignedTruth(const Trajectory& truth, const Trajectory& estimate) {
  std::vector<float> out;
  if (truth.empty() || estimate.size() < 3) return out;
  SE3 T_est_gt;
  try {
    T_est_gt = eval::ComputeAte(truth, estimate, FromSeconds(0.02)).T_gt_est.Inverse();
  } catch (const Error&) {  // too few poses associate yet
    return out;
  }
  out.reserve(3 * truth.size());
  for (const StampedPose& p : truth) {
    const Eigen::Vector3d q = T_est_gt * p.T_w_c.translation();
    out.insert(out.end(), {static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z())});
  }
  return out;
}

}  // namespace sgslam::viewer
