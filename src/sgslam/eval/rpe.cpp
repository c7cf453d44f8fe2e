#include "sgslam/eval/rpe.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <set>

#include "sgslam/common/error.h"
#include "sgslam/common/stats.h"

namespace sgslam::eval {

namespace {

std::vector<Timestamp> Stamps(const Trajectory& trajectory) {
  std::vector<Timestamp> stamps;
  stamps.reserve(trajectory.size());
  for (const StampedPose& p : trajectory) stamps.push_back(p.t);
  return stamps;
}

// compute_angle of evaluate_rpe.py. Near zero the arccos of the trace resolves
// angles no finer than ~1e-6 degrees; kept so the numbers match the script.
double RotationAngleDeg(const SE3& T) {
  const double c = std::clamp((T.rotation().trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / std::numbers::pi;
}

// The script samples random.sample(pairs, max_pairs); an evenly spaced subset keeps
// the same coverage of the sequence and makes every run give the same numbers.
std::vector<std::pair<std::size_t, std::size_t>> Thin(const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  out.reserve(kRpeMaxPairs);
  for (std::size_t k = 0; k < kRpeMaxPairs; ++k) out.push_back(pairs[k * pairs.size() / kRpeMaxPairs]);
  return out;
}

}  // namespace

std::size_t FindClosestIndex(const std::vector<Timestamp>& sorted, Timestamp t) {
  std::size_t begin = 0, end = sorted.size(), best = 0;
  Timestamp difference = std::llabs(sorted[0] - t);
  while (begin < end) {
    const std::size_t middle = (begin + end) / 2;
    if (std::llabs(sorted[middle] - t) < difference) {
      difference = std::llabs(sorted[middle] - t);
      best = middle;
    }
    if (sorted[middle] == t) return middle;
    if (sorted[middle] > t) {
      end = middle;
    } else {
      begin = middle + 1;
    }
  }
  return best;
}

RpeResult ComputeRpe(const Trajectory& gt, const Trajectory& est, Timestamp delta, const std::string& gt_name,
                     const std::string& est_name) {
  if (gt.size() < 2 || est.size() < 2) {
    throw InputError("RPE needs at least 2 poses in " + gt_name + " and in " + est_name);
  }
  const std::vector<Timestamp> gt_stamps = Stamps(gt), est_stamps = Stamps(est);
  // The script's overlap test: distinct estimate stamps reached by going to the
  // nearest gt stamp and back. Two disjoint time ranges collapse to one.
  std::set<Timestamp> returned;
  for (Timestamp t : est_stamps) {
    const Timestamp t_gt = gt_stamps[FindClosestIndex(gt_stamps, t)];
    returned.insert(est_stamps[FindClosestIndex(est_stamps, t_gt)]);
  }
  if (returned.size() < 2) {
    throw InputError("the timestamps of " + est_name + " and " + gt_name + " overlap too little for RPE");
  }

  std::vector<std::pair<std::size_t, std::size_t>> candidates;
  for (std::size_t i = 0; i < est_stamps.size(); ++i) {
    const std::size_t j = FindClosestIndex(est_stamps, est_stamps[i] + delta);
    // The script drops any pair ending on the last pose, not only those past the end.
    if (j != est_stamps.size() - 1) candidates.emplace_back(i, j);
  }
  RpeResult result;
  result.delta = delta;
  result.thinned = candidates.size() > kRpeMaxPairs;
  if (result.thinned) candidates = Thin(candidates);

  std::vector<double> intervals;
  for (std::size_t k = 1; k < gt_stamps.size(); ++k) {
    intervals.push_back(static_cast<double>(gt_stamps[k] - gt_stamps[k - 1]));
  }
  const double max_gt_gap = 2.0 * Median(intervals);  // ns

  std::vector<double> trans, rot;
  for (const auto& [i, j] : candidates) {
    RpePair p{i, j, FindClosestIndex(gt_stamps, est_stamps[i]), FindClosestIndex(gt_stamps, est_stamps[j])};
    if (static_cast<double>(std::llabs(gt_stamps[p.gt0] - est_stamps[i])) > max_gt_gap ||
        static_cast<double>(std::llabs(gt_stamps[p.gt1] - est_stamps[j])) > max_gt_gap) {
      continue;
    }
    // ominus(ominus(E1, E0), ominus(G1, G0)) with ominus(a, b) = a^-1 * b.
    const SE3 est_motion = est[j].T_w_c.Inverse() * est[i].T_w_c;
    const SE3 gt_motion = gt[p.gt1].T_w_c.Inverse() * gt[p.gt0].T_w_c;
    const SE3 error = est_motion.Inverse() * gt_motion;
    p.trans = error.translation().norm();
    p.rot_deg = RotationAngleDeg(error);
    trans.push_back(p.trans);
    rot.push_back(p.rot_deg);
    result.pairs.push_back(p);
  }
  if (result.pairs.size() < 2) {
    char spacing[32];
    std::snprintf(spacing, sizeof spacing, "%g s", ToSeconds(delta));
    throw InputError("only " + std::to_string(result.pairs.size()) + " pose pairs of " + est_name + " are " +
                     spacing + " apart with a pose of " + gt_name +
                     " near both ends; RPE needs 2 (is the estimate shorter than --delta?)");
  }
  result.trans = ComputeStats(trans);
  result.rot_deg = ComputeStats(rot);
  return result;
}

}  // namespace sgslam::eval
