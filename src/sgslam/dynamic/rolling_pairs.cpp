#include "sgslam/dynamic/rolling_pairs.h"

#include <cmath>

#include "sgslam/camera/rolling_shutter.h"
#include "sgslam/dynamic/depth_sample.h"
#include "sgslam/dynamic/motion.h"
#include "sgslam/optim/rolling_shutter_pose.h"

namespace sgslam::dynamic {

namespace {

Eigen::Vector3d Bearing(const cv::Point2f& un, const Pinhole& K) {
  return {(un.x - K.cx) / K.fx, (un.y - K.cy) / K.fy, 1.0};
}

cv::Point2f Project(const Eigen::Vector3d& p, const Pinhole& K) {
  return {static_cast<float>(K.fx * p.x() / p.z() + K.cx), static_cast<float>(K.fy * p.y() / p.z() + K.cy)};
}

// Seen along b at its row time s, the point lies along Exp(w s) b in the middle-row camera.
Eigen::Vector3d Turn(const Eigen::Vector3d& b, double raw_row, const Eigen::Vector3d& w, const RollingShutterInput& in) {
  return so3::Exp(w * RowTimeOffset(raw_row, in.height, in.readout)) * b;
}

}  // namespace

cv::Point2f ToMiddleRow(const cv::Point2f& un, double raw_row, const Eigen::Vector3d& w, const RollingShutterInput& in) {
  const Eigen::Vector3d b = Turn(Bearing(un, in.K), raw_row, w, in);
  return b.z() > 0 ? Project(b, in.K) : un;
}

RollingShutterFit CorrectPairsForRollingShutter(PairSet& pairs, const std::vector<bool>& use,
                                                const RollingShutterInput& in, const DynamicConfig& config) {
  RollingShutterFit fit;
  fit.w_cur = in.w_guess;
  if (!(in.readout > 0) || in.height <= 0) return fit;
  const std::size_t n = pairs.cur.size();
  const std::vector<cv::Point2f> cur_un = pairs.cur_un;  // as detected, turned again after the fit
  // The previous side: its velocity is known. A point lifted with the row camera's
  // depth (along that camera's axis) turns with its bearing.
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
  std::vector<double> row_time;
  std::vector<std::size_t> index;  // pair of each object point
  for (std::size_t i = 0; i < n; ++i) {
    if (pairs.flow.status[i] != PairStatus::kOk && pairs.flow.status[i] != PairStatus::kAppearance) continue;
    const cv::Point2f raw = pairs.flow.prev[i];
    const Eigen::Vector3d b = Turn(Bearing(pairs.prev_un[i], in.K), raw.y, in.w_prev, in);
    if (b.z() <= 0) continue;
    pairs.prev_un[i] = Project(b, in.K);
    pairs.cur_un[i] = ToMiddleRow(cur_un[i], pairs.cur[i].y, in.w_guess, in);
    if (!use[i] || in.prev_depth.empty()) continue;
    const int x = cvRound(raw.x), y = cvRound(raw.y);
    if (x < 0 || y < 0 || x >= in.prev_depth.cols || y >= in.prev_depth.rows) continue;
    const double z = DepthAt(in.prev_depth, x, y, in.depth_factor);
    if (!std::isfinite(z) || z < config.depth_min || z > config.depth_max) continue;
    const Eigen::Vector3d X = b * z;  // Bearing() has z = 1 before the turn
    object.emplace_back(static_cast<float>(X.x()), static_cast<float>(X.y()), static_cast<float>(X.z()));
    image.push_back(pairs.cur_un[i]);
    row_time.push_back(RowTimeOffset(pairs.cur[i].y, in.height, in.readout));
    index.push_back(i);
  }
  fit.pairs = static_cast<int>(object.size());
  const auto T = SolvePnPMotion(object, image, in.K, config.motion_iterations, config.motion_threshold,
                                config.motion_min_inliers);
  if (!T) return fit;
  // The velocity is fitted on the motion's inliers (a mover among them would bend
  // it). A strong bend leaves only a band of rows within the threshold of the
  // first, rigid motion, so the inliers are taken again under the fitted velocity
  // until they stop growing.
  const optim::Intrinsics K{in.K.fx, in.K.fy, in.K.cx, in.K.cy, 0.0};
  SE3 motion = *T;
  Eigen::Vector3d w = in.w_guess;
  constexpr int kRounds = 3;
  for (int round = 0; round < kRounds; ++round) {
    std::vector<optim::PoseObservation> obs;
    std::vector<double> times;
    for (std::size_t k = 0; k < object.size(); ++k) {
      const Eigen::Vector3d X(object[k].x, object[k].y, object[k].z);
      const Eigen::Vector3d p = motion * X;
      if (p.z() <= 0) continue;
      const cv::Point2f q = Project(p, in.K);
      if (std::hypot(q.x - image[k].x, q.y - image[k].y) > config.motion_threshold) continue;
      optim::PoseObservation o;
      o.p_w = X;
      o.uv = {image[k].x, image[k].y};
      obs.push_back(o);
      times.push_back(row_time[k]);
    }
    if (static_cast<int>(obs.size()) < config.motion_min_inliers || static_cast<int>(obs.size()) <= fit.inliers) break;
    const optim::RollingShutterPoseResult r = optim::OptimizePoseAndAngularVelocity(motion, obs, times, K);
    if (!r.ok || !r.delta.allFinite()) break;
    fit.inliers = static_cast<int>(obs.size());
    w += r.delta;
    motion = r.T_c_w;
    fit.fitted = true;
    for (std::size_t k = 0; k < object.size(); ++k) {  // the current points turned with the new velocity
      image[k] = ToMiddleRow(cur_un[index[k]], pairs.cur[index[k]].y, w, in);
    }
  }
  if (!fit.fitted) return fit;
  fit.w_cur = w;
  fit.T_cur_prev = motion;
  for (std::size_t i = 0; i < n; ++i) {
    if (pairs.flow.status[i] != PairStatus::kOk && pairs.flow.status[i] != PairStatus::kAppearance) continue;
    pairs.cur_un[i] = ToMiddleRow(cur_un[i], pairs.cur[i].y, fit.w_cur, in);
  }
  return fit;
}

}  // namespace sgslam::dynamic
