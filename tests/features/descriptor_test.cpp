// What OpenCV's ORB::compute does with keypoints we give it (OpenCV 4.x): the
// extractor relies on it keeping our angle, count and order for one-level,
// octave-0 keypoints, and on ComputeDescriptorsInOrder when it does not.
#include "sgslam/features/descriptor.h"

#include <gtest/gtest.h>

#include <random>

#include "feature_test_images.h"
#include "sgslam/features/fast_grid.h"

namespace sgslam::features {
namespace {

// Keypoints on a grid over [19, size - 19], the extractor's full range,
// with pseudo-random angles.
std::vector<cv::KeyPoint> GridKeypoints(cv::Size size, int step, int edge) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> angle(0.0f, 360.0f);
  std::vector<cv::KeyPoint> kps;
  for (int y = edge; y <= size.height - edge - 1; y += step) {
    for (int x = edge; x <= size.width - edge - 1; x += step) {
      kps.emplace_back(cv::Point2f(static_cast<float>(x), static_cast<float>(y)), 31.0f, angle(rng), 1.0f, 0);
    }
  }
  // The extreme corners too.
  kps.emplace_back(cv::Point2f(static_cast<float>(size.width - edge - 1), static_cast<float>(size.height - edge - 1)),
                   31.0f, 123.0f, 1.0f, 0);
  return kps;
}

TEST(RotatedBrief, OpenCvKeepsCountOrderAndAngleOfOneLevelKeypoints) {
  const cv::Mat image = test::UniformTexture(11);
  std::vector<cv::KeyPoint> kps = GridKeypoints(image.size(), 23, kEdgeThreshold);
  for (size_t i = 0; i < kps.size(); ++i) kps[i].class_id = static_cast<int>(i);
  const std::vector<cv::KeyPoint> given = kps;
  cv::Mat desc;
  MakeRotatedBrief()->compute(image, kps, desc);
  ASSERT_EQ(kps.size(), given.size()) << "OpenCV dropped keypoints";
  ASSERT_EQ(desc.rows, static_cast<int>(kps.size()));
  EXPECT_EQ(desc.cols, kDescriptorBytes);
  EXPECT_EQ(desc.type(), CV_8U);
  for (size_t i = 0; i < kps.size(); ++i) {
    EXPECT_EQ(kps[i].class_id, given[i].class_id) << "OpenCV reordered keypoints";
    EXPECT_EQ(kps[i].pt, given[i].pt);
    EXPECT_EQ(kps[i].angle, given[i].angle) << "OpenCV changed the angle";
    EXPECT_EQ(kps[i].octave, 0);
  }
}

TEST(RotatedBrief, DescriptorFollowsTheGivenAngle) {
  const cv::Mat image = test::UniformTexture(12);
  const cv::Ptr<cv::ORB> orb = MakeRotatedBrief();
  std::vector<cv::KeyPoint> a = {cv::KeyPoint(320, 240, 31, 0.0f)}, b = {cv::KeyPoint(320, 240, 31, 90.0f)};
  cv::Mat da, db, da2;
  orb->compute(image, a, da);
  orb->compute(image, b, db);
  orb->compute(image, a, da2);
  EXPECT_GT(cv::norm(da, db, cv::NORM_HAMMING), 40.0);  // rotating the pattern changes the bits
  EXPECT_EQ(cv::norm(da, da2, cv::NORM_HAMMING), 0.0);
}

// OpenCV drops keypoints within edgeThreshold of the border and groups them
// by octave; ComputeDescriptorsInOrder must still line rows up with keypoints.
TEST(RotatedBrief, InOrderSurvivesDropsAndRegrouping) {
  const cv::Mat image = test::UniformTexture(13);
  const cv::Ptr<cv::ORB> strict = cv::ORB::create(500, 1.2f, 2, /*edgeThreshold=*/31, 0, 2, cv::ORB::FAST_SCORE, 31);
  std::vector<cv::KeyPoint> kps = GridKeypoints(image.size(), 37, 19);
  for (size_t i = 0; i < kps.size(); ++i) {
    kps[i].octave = static_cast<int>(i % 3 == 0);  // octave-1 keypoints interleaved
    kps[i].class_id = 1000 + static_cast<int>(i);
  }

  // Raw OpenCV does both here, so the scenario is real.
  std::vector<cv::KeyPoint> raw = kps;
  cv::Mat raw_desc;
  strict->compute(image, raw, raw_desc);
  ASSERT_LT(raw.size(), kps.size());
  bool reordered = false;
  for (size_t i = 1; i < raw.size(); ++i) reordered |= raw[i].class_id < raw[i - 1].class_id;
  ASSERT_TRUE(reordered);

  std::vector<cv::KeyPoint> ordered = kps;
  cv::Mat desc;
  ComputeDescriptorsInOrder(strict, image, ordered, desc);
  ASSERT_EQ(ordered.size(), raw.size());
  ASSERT_EQ(desc.rows, static_cast<int>(ordered.size()));
  for (size_t i = 0; i < ordered.size(); ++i) {
    if (i > 0) {
      EXPECT_GT(ordered[i].class_id, ordered[i - 1].class_id) << "input order kept";
    }
    const cv::KeyPoint& in = kps[static_cast<size_t>(ordered[i].class_id - 1000)];
    EXPECT_EQ(ordered[i].pt, in.pt);
    EXPECT_EQ(ordered[i].octave, in.octave);
    // Row i is this keypoint's descriptor, computed alone.
    std::vector<cv::KeyPoint> one = {in};
    cv::Mat d1;
    strict->compute(image, one, d1);
    ASSERT_EQ(d1.rows, 1);
    EXPECT_EQ(cv::norm(desc.row(static_cast<int>(i)), d1, cv::NORM_HAMMING), 0.0) << i;
  }
  // Nothing in, nothing out, with the row width still set.
  std::vector<cv::KeyPoint> none;
  ComputeDescriptorsInOrder(strict, image, none, desc);
  EXPECT_EQ(desc.rows, 0);
  EXPECT_EQ(desc.cols, kDescriptorBytes);
}

}  // namespace
}  // namespace sgslam::features
