// Rotation invariance: rotating the image about its centre turns the
// orientation of corresponding keypoints by the same angle, and their rotated
// BRIEF descriptors still match.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "feature_test_images.h"
#include "sgslam/features/hamming.h"
#include "sgslam/features/orb_extractor.h"

namespace sgslam::features {
namespace {

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Wraps degrees into (-180, 180].
double Wrap(double deg) {
  deg = std::fmod(deg, 360.0);
  if (deg > 180.0) deg -= 360.0;
  if (deg <= -180.0) deg += 360.0;
  return deg;
}

struct RotationResult {
  int matches = 0;
  double median_angle_error = 0;  // deg, |angle change + rotation|
  double median_hamming = 0;      // bits of 256
};

RotationResult CompareUnderRotation(double rotation_deg) {
  const cv::Mat image = test::DiscTexture(21);
  const cv::Point2f centre(319.5f, 239.5f);
  const cv::Mat M = cv::getRotationMatrix2D(centre, rotation_deg, 1.0);
  cv::Mat rotated;
  cv::warpAffine(image, rotated, M, image.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(128));

  OrbExtractor orb(OrbConfig{});
  std::vector<cv::KeyPoint> k1, k2;
  cv::Mat d1, d2;
  orb.Extract(image, k1, d1);
  orb.Extract(rotated, k2, d2);

  RotationResult r;
  std::vector<double> angle_errors, hamming;
  for (size_t i = 0; i < k1.size(); ++i) {
    const cv::Point2f& p = k1[i].pt;
    const cv::Point2f q(static_cast<float>(M.at<double>(0, 0) * p.x + M.at<double>(0, 1) * p.y + M.at<double>(0, 2)),
                        static_cast<float>(M.at<double>(1, 0) * p.x + M.at<double>(1, 1) * p.y + M.at<double>(1, 2)));
    const double tolerance = 1.5 * orb.scale_factors()[static_cast<size_t>(k1[i].octave)];
    int best = -1;
    double best_dist = tolerance;
    for (size_t j = 0; j < k2.size(); ++j) {
      if (k2[j].octave != k1[i].octave) continue;
      const double d = cv::norm(k2[j].pt - q);
      if (d <= best_dist) {
        best_dist = d;
        best = static_cast<int>(j);
      }
    }
    if (best < 0) continue;
    // getRotationMatrix2D turns the image counter-clockwise on screen, which with
    // y pointing down is -rotation_deg in the keypoint angle's convention.
    angle_errors.push_back(std::abs(Wrap(k2[static_cast<size_t>(best)].angle - k1[i].angle + rotation_deg)));
    hamming.push_back(HammingDistance(d1.ptr<uint8_t>(static_cast<int>(i)), d2.ptr<uint8_t>(best)));
  }
  r.matches = static_cast<int>(angle_errors.size());
  if (r.matches > 0) {
    r.median_angle_error = Median(angle_errors);
    r.median_hamming = Median(hamming);
  }
  return r;
}

class Rotation : public ::testing::TestWithParam<double> {};

TEST_P(Rotation, AnglesTurnWithTheImageAndDescriptorsStillMatch) {
  const RotationResult r = CompareUnderRotation(GetParam());
  RecordProperty("matches", r.matches);
  RecordProperty("median_angle_error_deg", std::to_string(r.median_angle_error));
  RecordProperty("median_hamming", std::to_string(r.median_hamming));
  ASSERT_GE(r.matches, 100) << "too few repeated keypoints to judge";
  EXPECT_LT(r.median_angle_error, 3.0) << "matches " << r.matches;
  EXPECT_LT(r.median_hamming, 40.0) << "matches " << r.matches;
}

INSTANTIATE_TEST_SUITE_P(Angles, Rotation, ::testing::Values(30.0, 90.0, -45.0, 180.0));

// Sanity check of the matching itself: no rotation, identical keypoints.
TEST(Rotation, UnrotatedImageGivesIdenticalResults) {
  const RotationResult r = CompareUnderRotation(0.0);
  EXPECT_GE(r.matches, 500);
  EXPECT_EQ(r.median_angle_error, 0.0);
  EXPECT_EQ(r.median_hamming, 0.0);
}

}  // namespace
}  // namespace sgslam::features
