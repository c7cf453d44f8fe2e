#include "sgslam/features/orb_extractor.h"

#include <atomic>
#include <exception>
#include <string>
#include <thread>

#include "sgslam/common/error.h"
#include "sgslam/features/descriptor.h"
#include "sgslam/features/quadtree.h"

namespace sgslam::features {

namespace {

const OrbConfig& Validated(const OrbConfig& config) {
  ConfigChecker checker("orb");
  config.Validate(checker);
  if (!checker.problems().empty()) {
    std::string msg = "invalid ORB configuration:";
    for (const std::string& p : checker.problems()) msg += "\n  " + p;
    throw ConfigError(msg);
  }
  return config;
}

}  // namespace

OrbExtractor::OrbExtractor(const OrbConfig& config)
    : config_(Validated(config)),
      scales_(MakeScaleLevels(config.scale_factor, config.levels)),
      features_per_level_(FeaturesPerLevel(config.features, config.scale_factor, config.levels)),
      orientation_(kHalfPatchSize),
      brief_{MakeRotatedBrief(), MakeRotatedBrief()} {}

void OrbExtractor::Extract(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
  if (gray.empty() || gray.type() != CV_8UC1) {
    throw InputError("OrbExtractor::Extract needs a non-empty 8-bit grey image (CV_8UC1), got type " +
                     std::to_string(gray.type()) + " of size " + std::to_string(gray.cols) + "x" +
                     std::to_string(gray.rows));
  }
  BuildPyramid(gray, scales_.inv_scale, pyramid_);

  const int n = levels();
  std::vector<std::vector<cv::KeyPoint>> level_kps(static_cast<size_t>(n));
  std::vector<cv::Mat> level_desc(static_cast<size_t>(n));
  std::atomic<int> next{0};
  const auto work = [&](int worker) {
    for (int l = next.fetch_add(1); l < n; l = next.fetch_add(1))
      ExtractLevel(l, worker, level_kps[static_cast<size_t>(l)], level_desc[static_cast<size_t>(l)]);
  };
  if (threads_ > 1) {
    std::exception_ptr helper_error;
    std::thread helper([&] {
      try {
        work(1);
      } catch (...) {
        helper_error = std::current_exception();
      }
    });
    try {
      work(0);
    } catch (...) {
      next = n;  // the helper stops after its current level
      helper.join();
      throw;
    }
    helper.join();
    if (helper_error) std::rethrow_exception(helper_error);
  } else {
    work(0);
  }

  keypoints.clear();
  std::vector<cv::Mat> level_descriptors;
  for (int l = 0; l < n; ++l) {
    // To level-0 pixels; size and octave carry the level for matching and BA.
    const auto scale = static_cast<float>(scales_.scale[static_cast<size_t>(l)]);
    for (cv::KeyPoint& kp : level_kps[static_cast<size_t>(l)]) {
      kp.pt *= scale;
      kp.size = static_cast<float>(kPatchSize) * scale;
      kp.octave = l;
      keypoints.push_back(kp);
    }
    const cv::Mat& desc = level_desc[static_cast<size_t>(l)];
    if (!desc.empty()) level_descriptors.push_back(desc);
  }
  if (level_descriptors.empty()) {
    descriptors.create(0, kDescriptorBytes, CV_8U);
  } else {
    cv::vconcat(level_descriptors, descriptors);
  }
}

void OrbExtractor::ExtractLevel(int level, int worker, std::vector<cv::KeyPoint>& keypoints,
                                cv::Mat& descriptors) const {
  const cv::Mat& image = pyramid_[static_cast<size_t>(level)];
  FastCellParams fast;  // cells of 35 px (ORB-SLAM2)
  fast.threshold = config_.fast_threshold;
  fast.min_threshold = config_.fast_min_threshold;
  const std::vector<cv::KeyPoint> candidates = DetectFastInCells(image, fast);
  const cv::Rect region = DetectionRegion(image.size());
  keypoints = DistributeQuadtree(candidates, cv::Rect2f(region), features_per_level_[static_cast<size_t>(level)]);

  orientation_.Compute(image, keypoints);
  for (cv::KeyPoint& kp : keypoints) {
    kp.octave = 0;  // the level image is OpenCV's only level
    kp.size = static_cast<float>(kPatchSize);
  }
  ComputeDescriptorsInOrder(brief_[worker], image, keypoints, descriptors);
}

}  // namespace sgslam::features
