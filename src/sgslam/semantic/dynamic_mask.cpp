#include "sgslam/semantic/dynamic_mask.h"

#include "sgslam/semantic/box_window.h"

#include <algorithm>
#include <cmath>

namespace sgslam {

namespace {

// Around a rejected keypoint, only pixels this close to its depth are masked.
constexpr double kMotionDepthBand = 0.15;  // m
// Moving segments: depth grid step, the depth step that still joins neighbours (plus
// a term in depth^2), the rejected keypoints a segment needs (count and share), and
// the size above which a segment is background (walls, floor).
constexpr int kSegmentStep = 4;                 // px
constexpr double kSegmentJump = 0.02;           // m
constexpr double kSegmentJumpQuadratic = 0.02;  // 1/m
constexpr int kSegmentMinVotes = 3;
constexpr double kSegmentMinShare = 0.5;
constexpr double kSegmentMaxArea = 0.5;  // share of the image

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Depth segments on a grid (union-find over 4-neighbours whose depths differ by
// less than the jump tolerance); each segment where enough keypoints were
// rejected, and most of its keypoints, is masked whole.
void MaskMovingSegments(const cv::Mat& depth_raw, double depth_factor, const std::vector<cv::KeyPoint>& keys,
                        const std::vector<std::uint8_t>& rejected, const std::vector<std::uint8_t>& unjudged,
                        const DynamicMaskOptions& options, cv::Mat& mask, cv::Mat* also) {
  const int step = kSegmentStep;
  const int gw = (depth_raw.cols + step - 1) / step, gh = (depth_raw.rows + step - 1) / step;
  std::vector<float> z(static_cast<std::size_t>(gw) * gh);
  for (int gy = 0; gy < gh; ++gy)
    for (int gx = 0; gx < gw; ++gx)
      z[gy * gw + gx] = static_cast<float>(depth_raw.at<std::uint16_t>(gy * step, gx * step) / depth_factor);
  std::vector<int> parent(z.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  const auto join = [&](int a, int b) {
    const float za = z[a], zb = z[b];
    if (za <= 0 || zb <= 0) return;
    const double zm = std::min(za, zb);
    if (std::abs(za - zb) > kSegmentJump + kSegmentJumpQuadratic * zm * zm) return;
    parent[Find(parent, a)] = Find(parent, b);
  };
  for (int gy = 0; gy < gh; ++gy)
    for (int gx = 0; gx < gw; ++gx) {
      const int i = gy * gw + gx;
      if (gx + 1 < gw) join(i, i + 1);
      if (gy + 1 < gh) join(i, i + gw);
    }
  std::vector<int> area(z.size(), 0), votes(z.size(), 0), keys_in(z.size(), 0);
  for (std::size_t i = 0; i < z.size(); ++i)
    if (z[i] > 0) ++area[Find(parent, static_cast<int>(i))];
  const bool skip_unjudged = options.skip_unjudged && unjudged.size() == keys.size();
  for (std::size_t k = 0; k < keys.size(); ++k) {
    if (skip_unjudged && unjudged[k] != 0) continue;  // no test, no vote either way
    const int gx = cvRound(keys[k].pt.x / step), gy = cvRound(keys[k].pt.y / step);
    if (gx < 0 || gy < 0 || gx >= gw || gy >= gh || z[gy * gw + gx] <= 0) continue;
    const int root = Find(parent, gy * gw + gx);
    ++keys_in[root];
    votes[root] += rejected[k] ? 1 : 0;
  }
  const double max_area = kSegmentMaxArea * static_cast<double>(z.size());
  std::vector<std::uint8_t> moving(z.size(), 0);
  bool any = false;
  for (std::size_t r = 0; r < z.size(); ++r) {
    if (votes[r] < kSegmentMinVotes || area[r] > max_area) continue;
    if (votes[r] < kSegmentMinShare * keys_in[r]) continue;
    moving[r] = 1;
    any = true;
  }
  if (!any) return;
  std::vector<std::uint8_t> cell(z.size(), 0);
  for (std::size_t i = 0; i < z.size(); ++i) cell[i] = z[i] > 0 && moving[Find(parent, static_cast<int>(i))];
  for (int y = 0; y < depth_raw.rows; ++y) {
    std::uint8_t* m = mask.ptr<std::uint8_t>(y);
    std::uint8_t* a = also != nullptr ? also->ptr<std::uint8_t>(y) : nullptr;
    const std::uint8_t* row = &cell[static_cast<std::size_t>(std::min(gh - 1, (y + step / 2) / step)) * gw];
    for (int x = 0; x < depth_raw.cols; ++x) {
      if (!row[std::min(gw - 1, (x + step / 2) / step)]) continue;
      m[x] = 255;
      if (a != nullptr) a[x] = 255;
    }
  }
}

// Around each rejected keypoint not masked yet, the pixels within options.motion_radius
// whose depth lies within kMotionDepthBand of the keypoint's.
void MaskAroundRejected(const cv::Mat& depth_raw, double depth_factor, const std::vector<cv::KeyPoint>& keys,
                        const std::vector<std::uint8_t>& rejected, const DynamicMaskOptions& options, cv::Mat& mask) {
  const cv::Rect image(0, 0, depth_raw.cols, depth_raw.rows);
  const int radius = options.motion_radius;
  const double band_raw = kMotionDepthBand * depth_factor;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (!rejected[i]) continue;
    const int u = cvRound(keys[i].pt.x), v = cvRound(keys[i].pt.y);
    if (!image.contains({u, v}) || mask.at<std::uint8_t>(v, u) != 0) continue;  // inside a dynamic box already
    const double z = depth_raw.at<std::uint16_t>(v, u);
    if (z <= 0) continue;
    const int v0 = std::max(0, v - radius), v1 = std::min(depth_raw.rows - 1, v + radius);
    const int u0 = std::max(0, u - radius), u1 = std::min(depth_raw.cols - 1, u + radius);
    for (int y = v0; y <= v1; ++y) {
      const std::uint16_t* d = depth_raw.ptr<std::uint16_t>(y);
      std::uint8_t* m = mask.ptr<std::uint8_t>(y);
      const int dy = y - v;
      for (int x = u0; x <= u1; ++x) {
        const int dx = x - u;
        if (dx * dx + dy * dy > radius * radius || d[x] == 0) continue;
        if (std::abs(static_cast<double>(d[x]) - z) <= band_raw) m[x] = 255;
      }
    }
  }
}

}  // namespace

cv::Mat DynamicPixelMask(const cv::Mat& depth_raw, double depth_factor, const std::vector<Detection>& detections,
                         const ClassTable& classes, const std::vector<cv::KeyPoint>& keys,
                         const std::vector<std::uint8_t>& rejected, const DynamicMaskOptions& options,
                         const std::vector<std::uint8_t>& unjudged, cv::Mat* surface) {
  cv::Mat mask = cv::Mat::zeros(depth_raw.size(), CV_8UC1);
  if (surface != nullptr) *surface = cv::Mat::zeros(depth_raw.size(), CV_8UC1);
  const cv::Rect image(0, 0, depth_raw.cols, depth_raw.rows);
  for (const Detection& d : detections) {
    if (!classes.is_dynamic(d.class_name)) continue;
    const float mx = d.box.width * static_cast<float>(options.box_margin);
    const float my = d.box.height * static_cast<float>(options.box_margin);
    const cv::Rect grown(cv::Point(static_cast<int>(std::floor(d.box.x - mx)), static_cast<int>(std::floor(d.box.y - my))),
                         cv::Point(static_cast<int>(std::ceil(d.box.x + d.box.width + mx)),
                                   static_cast<int>(std::ceil(d.box.y + d.box.height + my))));
    const cv::Rect r = grown & image;
    if (r.area() <= 0) continue;
    mask(r).setTo(255);
    if (surface != nullptr) {
      // Only the object's surface: the pixels near the depth of the box's middle.
      const double z = BoxMedianDepth(depth_raw, depth_factor, d.box);
      if (z > 0) MaskCarriedBoxes({CarriedBox{cv::Rect2f(r), z}}, depth_raw, depth_factor, kSeenMovingBand, *surface);
    }
  }
  if (rejected.size() != keys.size()) return mask;
  if (options.motion_segments) MaskMovingSegments(depth_raw, depth_factor, keys, rejected, unjudged, options, mask, surface);
  if (options.motion_radius <= 0) return mask;
  MaskAroundRejected(depth_raw, depth_factor, keys, rejected, options, mask);
  if (surface != nullptr) MaskAroundRejected(depth_raw, depth_factor, keys, rejected, options, *surface);
  return mask;
}

}  // namespace sgslam
