#include "sgslam/semantic/box_window.h"

#include <algorithm>
#include <cmath>

#include "sgslam/camera/camera.h"

namespace sgslam {

double BoxMedianDepth(const cv::Mat& depth_raw, double depth_factor, const cv::Rect2f& box, double inner, int step) {
  if (depth_raw.empty() || depth_raw.type() != CV_16UC1 || depth_factor <= 0 || step < 1) return 0;
  const float sx = 0.5f * (1.f - static_cast<float>(inner)) * box.width;
  const float sy = 0.5f * (1.f - static_cast<float>(inner)) * box.height;
  const int x0 = std::max(0, static_cast<int>(box.x + sx)), y0 = std::max(0, static_cast<int>(box.y + sy));
  const int x1 = std::min(depth_raw.cols, static_cast<int>(box.x + box.width - sx));
  const int y1 = std::min(depth_raw.rows, static_cast<int>(box.y + box.height - sy));
  std::vector<std::uint16_t> z;
  for (int y = y0; y < y1; y += step) {
    const auto* row = depth_raw.ptr<std::uint16_t>(y);
    for (int x = x0; x < x1; x += step) {
      if (row[x] != 0) z.push_back(row[x]);
    }
  }
  if (z.empty()) return 0;
  auto mid = z.begin() + static_cast<std::ptrdiff_t>(z.size() / 2);
  std::nth_element(z.begin(), mid, z.end());
  return *mid / depth_factor;
}

std::vector<CarriedBox> CarryBoxes(const FrameBoxes& from, const SE3& T_c_w_to, const Camera& camera,
                                   cv::Size image, double growth_px, double max_area) {
  std::vector<CarriedBox> out;
  const SE3 T_to_from = T_c_w_to * from.T_c_w.Inverse();
  for (std::size_t b = 0; b < from.boxes.size() && b < from.depth.size(); ++b) {
    const double z = from.depth[b];
    if (!(z > 0)) continue;
    const cv::Rect2f& r = from.boxes[b].box;
    if (r.area() > max_area * image.area()) continue;
    // A 3x3 grid: corners and edge midpoints because lens distortion bends the
    // edges, and the centre (p[4], inside the box, so harmless to the bounds) for
    // the carried depth.
    std::vector<cv::Point2f> p;
    for (float fy : {0.f, 0.5f, 1.f}) {
      for (float fx : {0.f, 0.5f, 1.f}) p.emplace_back(r.x + fx * r.width, r.y + fy * r.height);
    }
    camera.Undistort(p);
    float u0 = 1e9f, v0 = 1e9f, u1 = -1e9f, v1 = -1e9f;
    bool behind = false;
    double depth = 0;
    for (std::size_t k = 0; k < p.size(); ++k) {
      const Eigen::Vector3d x = T_to_from * camera.Unproject(p[k].x, p[k].y, z);
      if (x.z() <= 0.1) {
        behind = true;
        break;
      }
      if (k == 4) depth = x.z();
      const Eigen::Vector2d uv = camera.Distort(camera.Project(x));
      u0 = std::min(u0, static_cast<float>(uv.x())), u1 = std::max(u1, static_cast<float>(uv.x()));
      v0 = std::min(v0, static_cast<float>(uv.y())), v1 = std::max(v1, static_cast<float>(uv.y()));
    }
    if (behind) continue;
    const auto g = static_cast<float>(growth_px);
    const cv::Rect2f moved(u0 - g, v0 - g, u1 - u0 + 2 * g, v1 - v0 + 2 * g);
    const cv::Rect2f clipped = moved & cv::Rect2f(0, 0, static_cast<float>(image.width), static_cast<float>(image.height));
    if (clipped.width <= 0 || clipped.height <= 0) continue;
    out.push_back({clipped, depth});
  }
  return out;
}

void MaskCarriedBoxes(const std::vector<CarriedBox>& boxes, const cv::Mat& depth_raw, double depth_factor,
                      double band, cv::Mat& mask) {
  if (depth_raw.type() != CV_16UC1 || mask.size() != depth_raw.size() || mask.type() != CV_8UC1) return;
  for (const CarriedBox& b : boxes) {
    const int x0 = std::max(0, static_cast<int>(b.box.x)), y0 = std::max(0, static_cast<int>(b.box.y));
    const int x1 = std::min(depth_raw.cols, static_cast<int>(std::ceil(b.box.x + b.box.width)));
    const int y1 = std::min(depth_raw.rows, static_cast<int>(std::ceil(b.box.y + b.box.height)));
    const auto lo = static_cast<float>(std::max(0.0, b.depth - band) * depth_factor);
    const auto hi = static_cast<float>((b.depth + band) * depth_factor);
    for (int y = y0; y < y1; ++y) {
      const auto* d = depth_raw.ptr<std::uint16_t>(y);
      auto* m = mask.ptr<std::uint8_t>(y);
      for (int x = x0; x < x1; ++x) {
        if (d[x] != 0 && d[x] >= lo && d[x] <= hi) m[x] = 255;
      }
    }
  }
}

}  // namespace sgslam
