#include "sgslam/dynamic/flow.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <opencv2/video/tracking.hpp>


namespace sgslam::dynamic {

namespace {

// Lucas-Kanade flow (line 1): the authors' release's settings.
constexpr int kLkWindow = 21;        // px, side of the square LK window
constexpr int kLkLevels = 3;         // pyramid levels above the full image (OpenCV maxLevel)
constexpr int kLkIterations = 30;    // per level
constexpr double kLkEpsilon = 0.01;  // px, LK stops when the update is smaller
// Pair filters (line 2, after DS-SLAM).
constexpr double kBorder = 8.0;  // px, pairs closer than this to an image edge (either image) are dropped
constexpr int kPatchRadius = 2;  // px, the appearance patch is (2r+1)^2 around both points (DS-SLAM's 5x5)

cv::Size Window() { return {kLkWindow, kLkWindow}; }

cv::TermCriteria Stop() { return {cv::TermCriteria::COUNT | cv::TermCriteria::EPS, kLkIterations, kLkEpsilon}; }

// An image or its pyramid, as calcOpticalFlowPyrLK takes either.
cv::_InputArray LkInput(const FlowFrame& f) {
  return f.pyramid.empty() ? cv::_InputArray(f.gray) : cv::_InputArray(f.pyramid);
}

bool Inside(cv::Point2f p, const cv::Size& size, double margin) {
  return p.x >= margin && p.y >= margin && p.x <= size.width - 1 - margin && p.y <= size.height - 1 - margin;
}

float Bilinear(const cv::Mat& image, float x, float y) {
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float ax = x - static_cast<float>(x0), ay = y - static_cast<float>(y0);
  const int x1 = std::min(x0 + 1, image.cols - 1), y1 = std::min(y0 + 1, image.rows - 1);
  const uchar* r0 = image.ptr<uchar>(y0);
  const uchar* r1 = image.ptr<uchar>(y1);
  return (1 - ay) * ((1 - ax) * r0[x0] + ax * r0[x1]) + ay * ((1 - ax) * r1[x0] + ax * r1[x1]);
}

}  // namespace

std::vector<cv::Mat> BuildFlowPyramid(const cv::Mat& gray) {
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(gray, pyramid, Window(), kLkLevels, true);
  return pyramid;
}

double PatchDifference(const cv::Mat& image_a, cv::Point2f a, const cv::Mat& image_b, cv::Point2f b, int radius) {
  const int side = 2 * radius + 1;
  std::vector<float> diff;
  diff.reserve(side * side);
  double mean = 0;
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx) {
      const auto fx = static_cast<float>(dx), fy = static_cast<float>(dy);
      diff.push_back(Bilinear(image_a, a.x + fx, a.y + fy) - Bilinear(image_b, b.x + fx, b.y + fy));
      mean += diff.back();
    }
  }
  // Zero-mean: an exposure change between the frames shifts every pixel alike and
  // says nothing about whether the pair is the same surface.
  mean /= static_cast<double>(diff.size());
  double sum = 0;
  for (float d : diff) sum += std::abs(d - mean);
  return sum / static_cast<double>(diff.size());
}

FlowPairs TrackBackward(const FlowFrame& prev, const FlowFrame& cur, const std::vector<cv::Point2f>& cur_points,
                        const FlowParams& params) {
  FlowPairs out;
  const size_t n = cur_points.size();
  out.status.assign(n, PairStatus::kFlowFailed);
  if (n == 0) return out;
  std::vector<uchar> ok;
  std::vector<float> err;
  // Line 1: P1 = CalcOpticalFlowPyrLK(F2, F1, P2), current -> previous.
  cv::calcOpticalFlowPyrLK(LkInput(cur), LkInput(prev), cur_points, out.prev, ok, err, Window(), kLkLevels,
                           Stop());
  // Line 2: drop failed flow, border pairs and pairs that changed appearance. The
  // margin also keeps the appearance patches inside both images.
  const double margin = std::max(kBorder, static_cast<double>(kPatchRadius) + 1.0);
  const cv::Size size = cur.gray.size();
  for (size_t i = 0; i < n; ++i) {
    PairStatus& s = out.status[i];
    if (!ok[i] || !std::isfinite(out.prev[i].x) || !std::isfinite(out.prev[i].y)) {
      s = PairStatus::kFlowFailed;
    } else if (!Inside(cur_points[i], size, margin) || !Inside(out.prev[i], size, margin)) {
      s = PairStatus::kBorder;
    } else if (PatchDifference(cur.gray, cur_points[i], prev.gray, out.prev[i], kPatchRadius) >
               params.max_patch_difference) {
      s = PairStatus::kAppearance;
    } else {
      s = PairStatus::kOk;
      ++out.valid;
    }
  }
  return out;
}

}  // namespace sgslam::dynamic
