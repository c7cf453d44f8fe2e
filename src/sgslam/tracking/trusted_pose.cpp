#include "sgslam/tracking/trusted_pose.h"

#include "sgslam/map/map_point.h"

namespace sgslam {

optim::PoseOptimizationResult OptimizePoseTrusted(const SE3& T_c_w_initial, std::vector<optim::PoseObservation> obs,
                                                  const std::vector<bool>& trusted, const optim::Intrinsics& K,
                                                  const TrustOptions& options, bool* trusted_start) {
  int n_trusted = 0;
  for (std::size_t k = 0; k < obs.size(); ++k) n_trusted += trusted[k] ? 1 : 0;
  const bool start = options.delay_s > 0 && n_trusted >= options.min_trusted;
  if (trusted_start) *trusted_start = start;
  if (!start) return optim::OptimizePose(T_c_w_initial, obs, K);

  for (std::size_t k = 0; k < obs.size(); ++k) obs[k].classify_only = !trusted[k];
  const optim::PoseOptimizationResult first = optim::OptimizePose(T_c_w_initial, obs, K);
  for (std::size_t k = 0; k < obs.size(); ++k) {
    if (trusted[k]) continue;
    obs[k].classify_only = false;
    obs[k].start_excluded = !first.inlier[k];
  }
  return optim::OptimizePose(first.T_c_w, obs, K);
}

void UpdateTrust(const Frame& frame, const TrustOptions& options) {
  if (options.delay_s <= 0) return;
  const auto delay = static_cast<Timestamp>(options.delay_s * static_cast<double>(kNsPerSecond));
  for (std::size_t i = 0; i < frame.map_points.size(); ++i) {
    const auto& p = frame.map_points[i];
    if (!p || frame.outlier[i] || p->track.trusted) continue;
    if (frame.t - p->created_t < delay) continue;
    if (++p->track.trust_hits >= options.hits) p->track.trusted = true;
  }
}

void TrustAll(const std::vector<std::shared_ptr<MapPoint>>& points) {
  for (const auto& p : points) {
    if (p) p->track.trusted = true;
  }
}

int CountTrustedInliers(const Frame& frame) {
  int n = 0;
  for (std::size_t i = 0; i < frame.map_points.size(); ++i) {
    const auto& p = frame.map_points[i];
    n += p && !frame.outlier[i] && p->track.trusted ? 1 : 0;
  }
  return n;
}

}  // namespace sgslam
