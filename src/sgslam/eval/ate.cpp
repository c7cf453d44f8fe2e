#include "sgslam/eval/ate.h"

#include <cstdio>

#include "sgslam/common/error.h"
#include "sgslam/geometry/rigid.h"
#include "sgslam/io/association.h"

namespace sgslam::eval {

namespace {

std::vector<Timestamp> Stamps(const Trajectory& trajectory) {
  std::vector<Timestamp> stamps;
  stamps.reserve(trajectory.size());
  for (const StampedPose& p : trajectory) stamps.push_back(p.t);
  return stamps;
}

std::string Seconds(Timestamp t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", ToSeconds(t));
  return buf;
}

}  // namespace

AteResult ComputeAte(const Trajectory& gt, const Trajectory& est, Timestamp max_difference,
                     const std::string& gt_name, const std::string& est_name,
                     const std::optional<SE3>& T_gt_est) {
  if (gt.empty()) throw InputError("ground truth " + gt_name + " contains no poses");
  if (est.empty()) throw InputError("estimate " + est_name + " contains no poses");
  AteResult result;
  result.pairs = AssociateByTime(Stamps(gt), Stamps(est), max_difference);
  if (result.pairs.empty()) {
    throw InputError("no pose of " + est_name + " is within " + Seconds(max_difference) + " s of one in " +
                     gt_name + "; check that both use the same clock in seconds, or raise --max-diff");
  }
  if (result.pairs.size() < 3 && !T_gt_est) {
    throw InputError("only " + std::to_string(result.pairs.size()) + " poses of " + est_name + " are within " +
                     Seconds(max_difference) + " s of one in " + gt_name +
                     "; a rigid alignment needs at least 3");
  }
  std::vector<Eigen::Vector3d> est_xyz, gt_xyz;
  for (const auto& [i, j] : result.pairs) {
    gt_xyz.push_back(gt[i].T_w_c.translation());
    est_xyz.push_back(est[j].T_w_c.translation());
  }
  result.T_gt_est = T_gt_est ? *T_gt_est : geometry::AlignRigid(est_xyz, gt_xyz);
  for (std::size_t k = 0; k < est_xyz.size(); ++k) {
    result.errors.push_back((result.T_gt_est * est_xyz[k] - gt_xyz[k]).norm());
  }
  result.stats = ComputeStats(result.errors);
  return result;
}

}  // namespace sgslam::eval
