#include "sgslam/semantic/cloud.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <unordered_map>

#include "sgslam/camera/camera.h"
#include "sgslam/semantic/voxel_cell.h"

namespace sgslam {

std::vector<ColoredPoint> VoxelDownsample(const std::vector<ColoredPoint>& in, double voxel) {
  struct Sum {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    double r = 0, g = 0, b = 0;
    int n = 0;
  };
  const double inv = 1.0 / voxel;
  std::unordered_map<std::uint64_t, std::size_t> index;
  index.reserve(in.size());
  std::vector<Sum> sums;
  for (const ColoredPoint& c : in) {
    if (!c.p.allFinite()) continue;
    const auto [it, fresh] = index.emplace(VoxelCell::Of(c.p.cast<double>(), inv).Key(), sums.size());
    if (fresh) sums.emplace_back();
    Sum& s = sums[it->second];
    s.p += c.p.cast<double>();
    s.r += c.rgb[0], s.g += c.rgb[1], s.b += c.rgb[2];
    ++s.n;
  }
  std::vector<ColoredPoint> out;
  out.reserve(sums.size());
  for (const Sum& s : sums) {
    const auto byte = [&](double v) { return static_cast<std::uint8_t>(std::lround(v / s.n)); };
    out.push_back({(s.p / s.n).cast<float>(), {byte(s.r), byte(s.g), byte(s.b)}});
  }
  return out;
}

PixelRays::PixelRays(const Camera& camera) : rays_(camera.height(), camera.width(), CV_32FC2) {
  std::vector<cv::Point2f> pixels;
  pixels.reserve(static_cast<std::size_t>(camera.width()) * static_cast<std::size_t>(camera.height()));
  for (int v = 0; v < camera.height(); ++v) {
    for (int u = 0; u < camera.width(); ++u) pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
  }
  camera.Undistort(pixels);  // the depth image is registered to the raw (distorted) colour image
  std::size_t k = 0;
  for (int v = 0; v < camera.height(); ++v) {
    for (int u = 0; u < camera.width(); ++u, ++k) {
      rays_.at<cv::Vec2f>(v, u) = {static_cast<float>((pixels[k].x - camera.cx()) / camera.fx()),
                                   static_cast<float>((pixels[k].y - camera.cy()) / camera.fy())};
    }
  }
}

namespace {

// A depth step: this much plus a term in depth^2 (Kinect noise grows with z^2).
constexpr double kEdgeJump = 0.05;           // m
constexpr double kEdgeJumpQuadratic = 0.02;  // 1/m

// A pixel within `radius` of a depth step larger than `jump` (either side): the
// eight pixels at that distance, holes ignored. Depth at an outline mixes the two
// surfaces (flying pixels), and the outline of a mover is where its mask and its
// depth disagree by a pixel or two.
bool OnDepthEdge(const cv::Mat& depth_raw, int u, int v, int radius, std::uint16_t d, double inv_factor,
                 double jump) {
  const int max_jump = static_cast<int>(jump / inv_factor);
  for (int dv = -radius; dv <= radius; dv += radius) {
    const int y = v + dv;
    if (y < 0 || y >= depth_raw.rows) continue;
    const std::uint16_t* row = depth_raw.ptr<std::uint16_t>(y);
    for (int du = -radius; du <= radius; du += radius) {
      const int x = u + du;
      if ((du == 0 && dv == 0) || x < 0 || x >= depth_raw.cols || row[x] == 0) continue;
      if (std::abs(static_cast<int>(row[x]) - static_cast<int>(d)) > max_jump) return true;
    }
  }
  return false;
}

}  // namespace

std::vector<ColoredPoint> BackProject(const cv::Mat& bgr, const cv::Mat& depth_raw, double depth_factor,
                                      const cv::Mat& mask, const PixelRays& rays, int stride,
                                      const SemanticConfig& config) {
  std::vector<ColoredPoint> out;
  if (depth_raw.empty() || depth_raw.type() != CV_16UC1 || depth_raw.size() != rays.size()) return out;
  const bool colour = !bgr.empty() && bgr.size() == depth_raw.size() && bgr.depth() == CV_8U;
  const int channels = colour ? bgr.channels() : 0;
  const double inv_factor = 1.0 / depth_factor;
  out.reserve(static_cast<std::size_t>(depth_raw.total() / static_cast<std::size_t>(stride * stride)));
  const int edge = config.filters.depth_edges ? kDepthEdgeRadius : 0;
  for (int v = 0; v < depth_raw.rows; v += stride) {
    const std::uint16_t* d = depth_raw.ptr<std::uint16_t>(v);
    const std::uint8_t* m = mask.empty() ? nullptr : mask.ptr<std::uint8_t>(v);
    for (int u = 0; u < depth_raw.cols; u += stride) {
      if (m != nullptr && m[u] != 0) continue;
      const double z = d[u] * inv_factor;
      if (d[u] == 0 || z < config.depth_min || z > config.depth_max) continue;
      if (edge > 0 && OnDepthEdge(depth_raw, u, v, edge, d[u], inv_factor,
                                  kEdgeJump + kEdgeJumpQuadratic * z * z)) {
        continue;
      }
      const cv::Vec2f& r = rays.at(u, v);
      ColoredPoint p;
      p.p = Eigen::Vector3f(static_cast<float>(r[0] * z), static_cast<float>(r[1] * z), static_cast<float>(z));
      if (channels >= 3) {
        const std::uint8_t* c = bgr.ptr<std::uint8_t>(v) + static_cast<std::ptrdiff_t>(u) * channels;
        p.rgb = {c[2], c[1], c[0]};
      } else if (channels == 1) {
        const std::uint8_t g = bgr.ptr<std::uint8_t>(v)[u];
        p.rgb = {g, g, g};
      }
      out.push_back(p);
    }
  }
  return out;
}

}  // namespace sgslam
