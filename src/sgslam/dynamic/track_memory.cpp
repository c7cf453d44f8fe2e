#include "sgslam/dynamic/track_memory.h"

#include <algorithm>
#include <cmath>

#include "sgslam/dynamic/motion.h"

namespace sgslam::dynamic {

namespace {

constexpr int kCell = 16;  // px, cell of the lookup grid

double DepthAt(const cv::Mat& depth, int x, int y, double depth_factor) {
  if (depth.type() == CV_16U) return depth.at<std::uint16_t>(y, x) / depth_factor;
  return depth.at<float>(y, x);
}

// Depth at p when its 3x3 neighbourhood is measured and agrees within the depth
// noise (no depth edge), else NaN.
double CleanDepth(const cv::Mat& depth, cv::Point2f p, double depth_factor, const DynamicConfig& c) {
  const int x = cvRound(p.x), y = cvRound(p.y);
  if (depth.empty() || x < 1 || y < 1 || x >= depth.cols - 1 || y >= depth.rows - 1) return std::nan("");
  double lo = 1e9, hi = -1e9;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const double z = DepthAt(depth, x + dx, y + dy, depth_factor);
      if (!std::isfinite(z) || z < c.depth_min || z > c.depth_max) return std::nan("");
      lo = std::min(lo, z), hi = std::max(hi, z);
    }
  }
  const double z = DepthAt(depth, x, y, depth_factor);
  if (hi - lo > c.depth_tolerance + c.depth_tolerance_quadratic * z * z) return std::nan("");
  return z;
}

}  // namespace

std::optional<SE3> TrackMemory::FitMotion(const std::vector<Eigen::Vector3d>& anchors,
                                          const std::vector<cv::Point2f>& image, const Pinhole& K,
                                          const DynamicConfig& c) const {
  std::vector<cv::Point3f> object;
  object.reserve(anchors.size());
  for (const auto& a : anchors) object.emplace_back(static_cast<float>(a.x()), static_cast<float>(a.y()), static_cast<float>(a.z()));
  return SolvePnPMotion(object, image, K, c.motion_iterations, c.track_fit_threshold, c.motion_min_inliers);
}

int TrackMemory::Nearest(cv::Point2f p, double r) const {
  if (grid_cols_ == 0) return -1;
  const int cx0 = std::max(0, static_cast<int>((p.x - r) / kCell)), cx1 = std::min(grid_cols_ - 1, static_cast<int>((p.x + r) / kCell));
  const int cy0 = std::max(0, static_cast<int>((p.y - r) / kCell)), cy1 = std::min(grid_rows_ - 1, static_cast<int>((p.y + r) / kCell));
  int best = -1;
  double best_d2 = r * r;
  for (int cy = cy0; cy <= cy1; ++cy) {
    for (int cx = cx0; cx <= cx1; ++cx) {
      for (int j : grid_[static_cast<std::size_t>(cy * grid_cols_ + cx)]) {
        const cv::Point2f d = tracks_[static_cast<std::size_t>(j)].pt - p;
        const double d2 = d.x * d.x + d.y * d.y;
        if (d2 <= best_d2) best_d2 = d2, best = j;  // ties: the later index, same every run
      }
    }
  }
  return best;
}

std::vector<TrackVerdict> TrackMemory::Update(const std::vector<cv::KeyPoint>& keys,
                                              const std::vector<cv::Point2f>& cur_un, const FlowPairs& flow,
                                              const std::vector<cv::Point2f>& prev_un,
                                              const cv::Mat& depth, double depth_factor, const Pinhole& K,
                                              const std::optional<SE3>& T_cur_prev, const DynamicConfig& c) {
  std::vector<TrackVerdict> out(keys.size());
  if (cur_un.size() != keys.size()) {  // no undistorted positions (first frame): start over next time
    tracks_.clear();
    grid_cols_ = grid_rows_ = 0;
    motion_.reset();
    motion_from_tracks_ = false;
    return out;
  }
  std::vector<Track> next(keys.size());
  // Association: the previous track each keypoint continues, its anchor shifted onto
  // the flow position (previous camera).
  std::vector<int> from(keys.size(), -1);
  std::vector<Eigen::Vector3d> carried(keys.size(), Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> fit_anchors;
  std::vector<cv::Point2f> fit_image;
  if (flow.prev.size() == keys.size() && prev_un.size() == keys.size()) {
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (flow.status[i] != PairStatus::kOk) continue;
      const double scale = std::max(1.0, static_cast<double>(keys[i].size) / 31.0);  // ORB: 31 px at level 0
      const int j = Nearest(flow.prev[i], c.track_radius * scale);
      if (j < 0 || tracks_[static_cast<std::size_t>(j)].age < 0) continue;
      const Track& p = tracks_[static_cast<std::size_t>(j)];
      const cv::Point2f shift = prev_un[i] - p.pt_un;  // px, flow position minus the old keypoint
      carried[i] = p.anchor + p.anchor.z() * Eigen::Vector3d(shift.x / K.fx, shift.y / K.fy, 0.0);
      from[i] = j;
      if (!p.moving) fit_anchors.push_back(carried[i]), fit_image.push_back(cur_un[i]);
    }
  }
  motion_from_tracks_ = false;
  motion_ = T_cur_prev;
  if (c.track_motion) {
    if (auto fitted = FitMotion(fit_anchors, fit_image, K, c)) motion_ = fitted, motion_from_tracks_ = true;
  }
  const bool chain = motion_.has_value();
  for (std::size_t i = 0; i < keys.size(); ++i) {
    Track& t = next[i];
    t.pt = keys[i].pt;
    t.pt_un = cur_un[i];
    if (chain && from[i] >= 0) {
      const Track& p = tracks_[static_cast<std::size_t>(from[i])];
      t.anchor = *motion_ * carried[i];
      t.age = p.age + 1;
      t.moving = p.moving;
      if (t.anchor.z() < c.depth_min) t.age = -1, t.moving = false;
    }
    if (t.age > 0) {
      const Eigen::Vector2d uv(K.fx * t.anchor.x() / t.anchor.z() + K.cx, K.fy * t.anchor.y() / t.anchor.z() + K.cy);
      const double residual = (uv - Eigen::Vector2d(cur_un[i].x, cur_un[i].y)).norm();
      out[i].residual = residual;
      if (t.age >= c.track_min_age) {
        t.moving = residual > c.track_tolerance + c.track_growth * std::sqrt(static_cast<double>(t.age));
      }
    }
    // A new anchor for keypoints without one, and for static tracks grown old.
    if (t.age < 0 || (!t.moving && t.age >= c.track_max_age)) {
      const double z = CleanDepth(depth, keys[i].pt, depth_factor, c);
      if (std::isfinite(z)) {
        t.anchor = Eigen::Vector3d((cur_un[i].x - K.cx) / K.fx * z, (cur_un[i].y - K.cy) / K.fy * z, z);
        t.age = 0;
      }  // else an old static track keeps chaining its old anchor
    }
    out[i].moving = t.moving;
    out[i].age = t.age;
  }
  tracks_ = std::move(next);
  grid_cols_ = depth.empty() ? 0 : (depth.cols + kCell - 1) / kCell;
  grid_rows_ = depth.empty() ? 0 : (depth.rows + kCell - 1) / kCell;
  grid_.assign(static_cast<std::size_t>(grid_cols_ * grid_rows_), {});
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    const int cx = static_cast<int>(tracks_[i].pt.x) / kCell, cy = static_cast<int>(tracks_[i].pt.y) / kCell;
    if (tracks_[i].pt.x < 0 || tracks_[i].pt.y < 0 || cx >= grid_cols_ || cy >= grid_rows_) continue;
    grid_[static_cast<std::size_t>(cy * grid_cols_ + cx)].push_back(static_cast<int>(i));
  }
  return out;
}

}  // namespace sgslam::dynamic
