#include "support/tiny_dataset.h"

#include <opencv2/imgcodecs.hpp>
#include <algorithm>
#include <string>

#include "sgslam/common/time.h"
#include "support/test_support.h"

namespace sgslam::test {

namespace fs = std::filesystem;

CameraConfig TinyCamera() {
  CameraConfig c;
  c.width = 64;
  c.height = 48;
  c.fx = c.fy = 50.0;
  c.cx = 31.5;
  c.cy = 23.5;
  c.k1 = c.k2 = c.p1 = c.p2 = c.k3 = 0.0;
  return c;
}

void WriteTinyDataset(const fs::path& dir, int n, Timestamp period) {
  fs::create_directories(dir / "rgb");
  fs::create_directories(dir / "depth");
  std::string rgb_list = "# color images\n", depth_list = "# depth maps\n";
  for (int i = 0; i < n; ++i) {
    const Timestamp t = 1000 * kNsPerSecond + i * period;
    const std::string ts = FormatTimestamp(t), td = FormatTimestamp(t + std::min<Timestamp>(5'000'000, period / 5));
    cv::Mat bgr(48, 64, CV_8UC3, cv::Scalar(40 + i, 90, 160));
    cv::Mat depth(48, 64, CV_16UC1, cv::Scalar(10000));  // 2 m at factor 5000
    cv::imwrite((dir / "rgb" / (ts + ".png")).string(), bgr);
    cv::imwrite((dir / "depth" / (td + ".png")).string(), depth);
    rgb_list += ts + " rgb/" + ts + ".png\n";
    depth_list += td + " depth/" + td + ".png\n";
  }
  WriteText(dir / "rgb.txt", rgb_list);
  WriteText(dir / "depth.txt", depth_list);
  WriteText(dir / "sgslam.yaml",
            "camera:\n  width: 64\n  height: 48\n  fx: 50\n  fy: 50\n  cx: 31.5\n  cy: 23.5\n"
            "  k1: 0\n  k2: 0\n  p1: 0\n  p2: 0\n  k3: 0\n");
}

}  // namespace sgslam::test
