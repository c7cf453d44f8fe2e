#include "sgslam/detection/people_scale.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <spdlog/spdlog.h>

#include "sgslam/common/stats.h"
#include "sgslam/io/tum_dataset.h"

namespace sgslam {

namespace {

constexpr float kMinScore = 0.5f;  // a confident person: a part-person box would mislead
constexpr int kEdge = 3;           // px from the top or bottom: the person may go on beyond

std::string Metres(double m) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f m", m);
  return buf;
}

}  // namespace

std::optional<double> PersonHeight(const cv::Mat& depth, const Detection& d, const CameraConfig& camera) {
  if (d.class_name != "person" || d.score < kMinScore || d.carried != 0 || depth.type() != CV_16UC1) {
    return std::nullopt;
  }
  const cv::Rect2f& b = d.box;
  if (!(b.height >= 20 && b.width >= 4) || b.y < kEdge || b.y + b.height > depth.rows - kEdge) return std::nullopt;
  const int u0 = std::max(0, static_cast<int>(b.x + b.width / 4));
  const int u1 = std::min(depth.cols, static_cast<int>(b.x + 3 * b.width / 4));
  const int v0 = std::max(0, static_cast<int>(b.y));
  const int v1 = std::min(depth.rows, static_cast<int>(b.y + b.height));
  std::vector<std::uint16_t> raw;
  for (int v = v0; v < v1; v += 2) {
    const auto* row = depth.ptr<std::uint16_t>(v);
    for (int u = u0; u < u1; u += 2) {
      if (row[u] != 0) raw.push_back(row[u]);
    }
  }
  const std::size_t cells = static_cast<std::size_t>(std::max(0, (v1 - v0 + 1) / 2) * std::max(0, (u1 - u0 + 1) / 2));
  if (raw.size() < 20 || raw.size() * 4 < cells) return std::nullopt;  // under a quarter of the box measured
  const auto quartile = raw.begin() + static_cast<std::ptrdiff_t>(raw.size() / 4);
  std::nth_element(raw.begin(), quartile, raw.end());
  const double z = *quartile / camera.depth_factor;
  return b.height * z / camera.fy;
}

std::optional<std::string> PeopleScaleCheck::Add(const cv::Mat& depth, const std::vector<Detection>& detections,
                                                 const CameraConfig& camera) {
  if (judged_) return std::nullopt;
  for (const Detection& d : detections) {
    if (const auto h = PersonHeight(depth, d, camera)) {
      spdlog::debug("depth scale: a person {:.0f} px tall measures {:.2f} m", d.box.height, *h);
      heights_.push_back(*h);
    }
  }
  if (measured() < kPeopleNeeded) return std::nullopt;
  judged_ = true;
  const auto [lo, hi] = std::minmax_element(heights_.begin(), heights_.end());
  const bool tiny = *hi < kMinTallest, giant = *lo > kMaxShortest;
  if (!tiny && !giant) return std::nullopt;
  const double seen = tiny ? *hi : *lo;
  char factor[32];
  std::snprintf(factor, sizeof factor, "%g", camera.depth_factor);
  const std::string hint = DepthFactorHint(seen, camera.depth_factor, kMinTallest, kMaxShortest);
  const std::string n = std::to_string(measured());
  return (tiny ? "the tallest of the " + n + " people measured in the first frames is " + Metres(seen) +
                     ", where even a head and shoulders are " + Metres(kMinTallest)
               : "the shortest of the " + n + " people measured in the first frames is " + Metres(seen) +
                     ", where no one is " + Metres(kMaxShortest)) +
         ", with camera.depth_factor = " + factor + hint +
         ". Check camera.depth_factor (TUM and Bonn use 5000, millimetre depth 1000)";
}

std::optional<double> PeopleScaleCheck::median_height() const {
  if (heights_.empty()) return std::nullopt;
  return Median(heights_);
}

std::optional<double> PeopleScaleCheck::tallest() const {
  if (heights_.empty()) return std::nullopt;
  return *std::max_element(heights_.begin(), heights_.end());
}

}  // namespace sgslam
