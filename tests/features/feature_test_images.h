// Seeded synthetic images for the feature tests: texture whose corners FAST
// finds, with no data files needed.
#pragma once

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

namespace sgslam::test {

// `count` random filled rectangles, sides in [min_side, max_side] px, grey
// levels uniform in [lo, hi], drawn over `image` inside `area`.
inline void DrawRandomBlocks(cv::Mat& image, const cv::Rect& area, int count, int min_side, int max_side, int lo,
                             int hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> x(area.x, area.br().x - 1), y(area.y, area.br().y - 1);
  std::uniform_int_distribution<int> side(min_side, max_side), grey(lo, hi);
  for (int i = 0; i < count; ++i) {
    const cv::Rect r(x(rng), y(rng), side(rng), side(rng));
    image(r & area).setTo(grey(rng));
  }
}

// Texture of the same statistics everywhere.
inline cv::Mat UniformTexture(unsigned seed, cv::Size size = {640, 480}) {
  cv::Mat image(size, CV_8UC1, cv::Scalar(128));
  DrawRandomBlocks(image, cv::Rect({0, 0}, size), size.area() / 60, 4, 24, 0, 255, seed);
  cv::GaussianBlur(image, image, cv::Size(3, 3), 0.8);
  return image;
}

// Strong texture in the top-left 200x150 px; elsewhere only faint texture
// (contrast < 20, so only FAST's fallback threshold finds corners there).
inline cv::Mat CornerTexture(unsigned seed) {
  cv::Mat image(480, 640, CV_8UC1, cv::Scalar(120));
  DrawRandomBlocks(image, cv::Rect(0, 0, 640, 480), 640 * 480 / 40, 4, 16, 102, 120, seed);
  DrawRandomBlocks(image, cv::Rect(0, 0, 200, 150), 200 * 150 / 25, 3, 12, 0, 255, seed + 1);
  return image;
}

// Smooth texture faded out towards a disc of radius `radius` about the image
// centre, flat grey outside: rotating it about the centre loses nothing.
inline cv::Mat DiscTexture(unsigned seed, double radius = 215.0) {
  cv::Mat texture(480, 640, CV_8UC1, cv::Scalar(128));
  DrawRandomBlocks(texture, cv::Rect(0, 0, 640, 480), 2500, 6, 28, 20, 235, seed);
  cv::GaussianBlur(texture, texture, cv::Size(0, 0), 1.2);
  cv::Mat image(480, 640, CV_8UC1);
  const cv::Point2d c(319.5, 239.5);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const double r = std::hypot(x - c.x, y - c.y);
      const double w = std::clamp((radius - r) / 20.0, 0.0, 1.0);  // 20 px fade, no corners at the rim
      image.at<uchar>(y, x) = cv::saturate_cast<uchar>(128.0 + w * (texture.at<uchar>(y, x) - 128.0));
    }
  }
  return image;
}

}  // namespace sgslam::test
