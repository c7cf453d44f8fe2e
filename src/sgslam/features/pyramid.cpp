#include "sgslam/features/pyramid.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace sgslam::features {

ScaleLevels MakeScaleLevels(double scale_factor, int levels) {
  ScaleLevels s;
  s.levels = levels;
  s.factor = scale_factor;
  s.log_factor = std::log(scale_factor);
  double scale = 1.0;
  for (int l = 0; l < levels; ++l) {
    s.scale.push_back(scale);
    s.inv_scale.push_back(1.0 / scale);
    s.sigma2.push_back(scale * scale);
    s.inv_sigma2.push_back(1.0 / (scale * scale));
    scale *= scale_factor;
  }
  return s;
}

std::vector<int> FeaturesPerLevel(int features, double scale_factor, int levels) {
  std::vector<int> n(static_cast<size_t>(levels), 0);
  const double r = 1.0 / scale_factor;
  double desired = features * (1.0 - r) / (1.0 - std::pow(r, levels));
  int sum = 0;
  for (int l = 0; l + 1 < levels; ++l) {
    n[static_cast<size_t>(l)] = static_cast<int>(std::lround(desired));
    sum += n[static_cast<size_t>(l)];
    desired *= r;
  }
  n.back() = std::max(features - sum, 0);
  return n;
}

void BuildPyramid(const cv::Mat& gray, const std::vector<double>& inv_scale, std::vector<cv::Mat>& pyramid) {
  pyramid.resize(inv_scale.size());
  for (size_t l = 0; l < inv_scale.size(); ++l) {
    if (l == 0) {
      gray.copyTo(pyramid[0]);
      continue;
    }
    const cv::Size size(cvRound(gray.cols * inv_scale[l]), cvRound(gray.rows * inv_scale[l]));
    cv::resize(pyramid[l - 1], pyramid[l], size, 0, 0, cv::INTER_LINEAR);
  }
}

}  // namespace sgslam::features
