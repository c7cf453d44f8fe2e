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

// The pairs of gt and est, at least min_pairs of them.
std::vector<std::pair<std::size_t, std::size_t>> Associate(const Trajectory& gt, const Trajectory& est,
                                                           Timestamp max_difference, std::size_t min_pairs,
                                                           const std::string& gt_name, const std::string& est_name) {
  if (gt.empty()) throw InputError("ground truth " + gt_name + " contains no poses");
  if (est.empty()) throw InputError("estimate " + est_name + " contains no poses");
  auto pairs = AssociateByTime(Stamps(gt), Stamps(est), max_difference);
  if (pairs.empty()) {
    throw InputError("no pose of " + est_name + " is within " + Seconds(max_difference) + " s of one in " +
                     gt_name + "; check that both use the same clock in seconds, or raise --max-diff");
  }
  if (pairs.size() < min_pairs) {
    throw InputError("only " + std::to_string(pairs.size()) + " poses of " + est_name + " are within " +
                     Seconds(max_difference) + " s of one in " + gt_name + "; a rigid alignment needs at least " +
                     std::to_string(min_pairs));
  }
  return pairs;
}

void AddErrors(const Trajectory& gt, const Trajectory& est, AteResult& result) {
  for (const auto& [i, j] : result.pairs) {
    result.errors.push_back((result.T_gt_est * est[j].T_w_c.translation() - gt[i].T_w_c.translation()).norm());
  }
  result.stats = ComputeStats(result.errors);
}

}  // namespace

AteResult ComputeAte(const Trajectory& gt, const Trajectory& est, Timestamp max_difference,
                     const std::string& gt_name, const std::string& est_name) {
  AteResult result;
  result.pairs = Associate(gt, est, max_difference, 3, gt_name, est_name);
  std::vector<Eigen::Vector3d> est_xyz, gt_xyz;
  for (const auto& [i, j] : result.pairs) {
    gt_xyz.push_back(gt[i].T_w_c.translation());
    est_xyz.push_back(est[j].T_w_c.translation());
  }
  result.T_gt_est = geometry::AlignRigid(est_xyz, gt_xyz);
  AddErrors(gt, est, result);
  return result;
}

AteResult ComputeAteAt(const Trajectory& gt, const Trajectory& est, const SE3& T_gt_est, Timestamp max_difference,
                       const std::string& gt_name, const std::string& est_name) {
  AteResult result;
  result.pairs = Associate(gt, est, max_difference, 1, gt_name, est_name);
  result.T_gt_est = T_gt_est;
  AddErrors(gt, est, result);
  return result;
}

}  // namespace sgslam::eval
