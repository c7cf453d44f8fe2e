#include "map_plot.h"

#include <algorithm>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sgslam/common/error.h"
#include "sgslam/common/stats.h"
#include "sgslam/io/atomic_write.h"

namespace sgslam::app {

void WriteTopView(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& cloud,
                  const std::vector<Rgb>& colours, const std::vector<ObjectEstimate>& objects,
                  const Trajectory& trajectory) {
  std::vector<double> xs, zs;
  for (const auto& p : cloud) xs.push_back(p.x()), zs.push_back(p.z());
  for (const auto& s : trajectory) xs.push_back(s.T_w_c.translation().x()), zs.push_back(s.T_w_c.translation().z());
  if (xs.empty()) xs = {-1, 1}, zs = {-1, 1};
  double x0 = Percentile(xs, 0.01) - 0.2, x1 = Percentile(xs, 0.99) + 0.2;
  double z0 = Percentile(zs, 0.01) - 0.2, z1 = Percentile(zs, 0.99) + 0.2;
  // Every object box whole, with room above it for its label (the cloud's 1-99
  // percentiles can cut a box at the edge of the map).
  for (const ObjectEstimate& o : objects) {
    if (!o.exported) continue;
    x0 = std::min(x0, o.centroid.x() - o.size.x() / 2 - 0.1);
    x1 = std::max(x1, o.centroid.x() + o.size.x() / 2 + 0.1);
    z0 = std::min(z0, o.centroid.z() - o.size.z() / 2 - 0.1);
    z1 = std::max(z1, o.centroid.z() + o.size.z() / 2 + 0.3);
  }
  const int width = 900;
  const double scale = width / std::max(x1 - x0, 1e-3);
  const int height = std::clamp(static_cast<int>((z1 - z0) * scale), 200, 2000);
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const auto px = [&](double x, double z) {
    return cv::Point(static_cast<int>((x - x0) * scale), static_cast<int>((z1 - z) * scale));
  };
  // Highest points last (y points down): the view from above shows tops.
  std::vector<std::size_t> order(cloud.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return cloud[a].y() > cloud[b].y(); });
  for (std::size_t i : order) {
    const cv::Point p = px(cloud[i].x(), cloud[i].z());
    if (p.x < 0 || p.y < 0 || p.x >= width || p.y >= height) continue;
    const Rgb c = i < colours.size() ? colours[i] : Rgb{90, 90, 90};
    image.at<cv::Vec3b>(p) = cv::Vec3b(c[2], c[1], c[0]);
  }
  for (std::size_t i = 1; i < trajectory.size(); ++i) {
    cv::line(image, px(trajectory[i - 1].T_w_c.translation().x(), trajectory[i - 1].T_w_c.translation().z()),
             px(trajectory[i].T_w_c.translation().x(), trajectory[i].T_w_c.translation().z()), cv::Scalar(0, 0, 220), 2,
             cv::LINE_AA);
  }
  std::vector<cv::Rect> labels;  // placed so far: a label that would overlap one moves down a line
  for (const ObjectEstimate& o : objects) {
    if (!o.exported) continue;
    const cv::Point a = px(o.centroid.x() - o.size.x() / 2, o.centroid.z() - o.size.z() / 2);
    const cv::Point b = px(o.centroid.x() + o.size.x() / 2, o.centroid.z() + o.size.z() / 2);
    // A partial object (never seen whole, objects.h) gets a thin outline and a '?'.
    cv::rectangle(image, a, b, cv::Scalar(200, 120, 0), o.complete ? 2 : 1);
    const std::string text = o.complete ? o.class_name : o.class_name + "?";
    int baseline = 0;
    const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, 0.5, 1, &baseline);
    cv::Point at(std::min(a.x, b.x), std::min(a.y, b.y) - 4);
    for (int tries = 0; tries < 8; ++tries) {
      const cv::Rect r(at.x, at.y - size.height, size.width, size.height + baseline);
      if (std::none_of(labels.begin(), labels.end(), [&](const cv::Rect& l) { return (l & r).area() > 0; })) break;
      at.y += size.height + baseline + 2;
    }
    labels.emplace_back(at.x, at.y - size.height, size.width, size.height + baseline);
    cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(200, 120, 0), 1, cv::LINE_AA);
  }
  const int bar = static_cast<int>(scale);  // 1 m scale bar
  cv::line(image, {20, height - 20}, {20 + bar, height - 20}, cv::Scalar(0, 0, 0), 2);
  cv::putText(image, "1 m", {20, height - 28}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", image, png)) throw InputError("cannot encode " + path.string());
  WriteFileAtomically(path, std::string(png.begin(), png.end()));
}

}  // namespace sgslam::app
