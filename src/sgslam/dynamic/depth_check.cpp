#include "sgslam/dynamic/depth_check.h"

#include "sgslam/dynamic/depth_sample.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sgslam::dynamic {

namespace {

bool InRange(double z) { return std::isfinite(z) && z >= kDepthMin && z <= kDepthMax; }

std::vector<cv::Point2f> Undistorted(const DepthCheckInput& in, const std::vector<cv::Point2f>& p) {
  if (!in.undistort) return p;
  std::vector<cv::Point2f> out(p.size());
  for (size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d u = in.undistort(Eigen::Vector2d(p[i].x, p[i].y));
    out[i] = cv::Point2f(static_cast<float>(u.x()), static_cast<float>(u.y()));
  }
  return out;
}

}  // namespace

std::vector<DepthResidual> CheckDepth(const std::vector<cv::Point2f>& prev, const std::vector<cv::Point2f>& cur,
                                      const std::vector<bool>& use, const DepthCheckInput& input,
                                      const DepthCheckParams& params) {
  return CheckDepth(prev, cur, Undistorted(input, prev), Undistorted(input, cur), use, input, params);
}

std::vector<DepthResidual> CheckDepth(const std::vector<cv::Point2f>& prev, const std::vector<cv::Point2f>& cur,
                                      const std::vector<cv::Point2f>& prev_un, const std::vector<cv::Point2f>& cur_un,
                                      const std::vector<bool>& use, const DepthCheckInput& input,
                                      const DepthCheckParams& params) {
  std::vector<DepthResidual> out(prev.size());
  const cv::Mat& d0 = input.prev_depth;
  const cv::Mat& d1 = input.cur_depth;
  if (d0.empty() || d1.empty()) return out;
  const Pinhole& K = input.K;
  const int w = params.window;
  const int m0 = std::max(1, w);  // the previous window must lie inside the image
  for (size_t i = 0; i < prev.size(); ++i) {
    if (!use[i]) continue;
    const int x0 = cvRound(prev[i].x), y0 = cvRound(prev[i].y);
    const int x1 = cvRound(cur[i].x), y1 = cvRound(cur[i].y);
    if (x0 < m0 || y0 < m0 || x0 >= d0.cols - m0 || y0 >= d0.rows - m0) continue;
    if (x1 < 1 || y1 < 1 || x1 >= d1.cols - 1 || y1 >= d1.rows - 1) continue;
    if (!InRange(DepthAt(d0, x0, y0, input.depth_factor))) continue;
    const Eigen::Vector2d u0(prev_un[i].x, prev_un[i].y);
    const Eigen::Vector2d u1(cur_un[i].x, cur_un[i].y);
    // Each previous depth of the window lifts the point; the smallest depth error
    // (against the current 3x3, below) and the smallest reprojection error count:
    // a static point next to a depth edge must not be flagged because rounding (or
    // fr1's depth-to-colour offset) picked the other surface.
    double best = std::numeric_limits<double>::infinity(), best_rep = best, z_at_best = 0;
    for (int py = -w; py <= w; ++py) {
      for (int px = -w; px <= w; ++px) {
        const double zp = DepthAt(d0, x0 + px, y0 + py, input.depth_factor);
        if (!InRange(zp)) continue;
        const Eigen::Vector3d X_prev((u0.x() - K.cx) / K.fx * zp, (u0.y() - K.cy) / K.fy * zp, zp);
        const Eigen::Vector3d X_cur = input.T_cur_prev * X_prev;
        if (X_cur.z() < kDepthMin) continue;
        const Eigen::Vector2d projected(K.fx * X_cur.x() / X_cur.z() + K.cx, K.fy * X_cur.y() / X_cur.z() + K.cy);
        best_rep = std::min(best_rep, (projected - u1).norm());
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const double z = DepthAt(d1, x1 + dx, y1 + dy, input.depth_factor);
            if (InRange(z) && std::abs(X_cur.z() - z) < best) best = std::abs(X_cur.z() - z), z_at_best = X_cur.z();
          }
        }
      }
    }
    if (!std::isfinite(best) || !std::isfinite(best_rep)) continue;
    DepthResidual& r = out[i];
    r.valid = true;
    r.depth_error = best;
    r.reprojection_error = best_rep;
    const double z_tolerance = kDepthTolerance + kDepthToleranceQuadratic * z_at_best * z_at_best;
    r.moved = r.depth_error > z_tolerance;
    r.depth_tolerance = z_tolerance;
  }
  if (params.reprojection_tolerance > 0) {
    // The frame's own residual level: under fast rotation the static points' residuals
    // grow together (rolling shutter, an imprecise motion), a mover's stand out.
    std::vector<double> e;
    for (const DepthResidual& r : out) {
      if (r.valid) e.push_back(r.reprojection_error);
    }
    double tolerance = params.reprojection_tolerance;
    constexpr std::size_t kMinForMedian = 20;  // fewer: no level to speak of, the fixed tolerance
    if (input.median_level && params.reprojection_median_factor > 0 && e.size() >= kMinForMedian) {
      auto mid = e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2);
      std::nth_element(e.begin(), mid, e.end());
      tolerance = std::max(tolerance, params.reprojection_median_factor * *mid);
    }
    for (DepthResidual& r : out) {
      r.reprojection_tolerance = tolerance;
      r.moved = r.moved || (r.valid && r.reprojection_error > tolerance);
    }
  }
  return out;
}

}  // namespace sgslam::dynamic
