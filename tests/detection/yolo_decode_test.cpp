#include "sgslam/detection/yolo_decode.h"

#include <gtest/gtest.h>

#include <limits>

namespace sgslam {
namespace {

const std::vector<std::string> kNames = {"person", "bicycle", "car"};

// One output row as OpenCV's [yolo] layer writes it: box relative to the input,
// objectness, then objectness-times-class scores.
void AddRow(cv::Mat& out, float cx, float cy, float w, float h, std::vector<float> scores) {
  cv::Mat row(1, 5 + static_cast<int>(kNames.size()), CV_32F, cv::Scalar(0));
  row.at<float>(0) = cx;
  row.at<float>(1) = cy;
  row.at<float>(2) = w;
  row.at<float>(3) = h;
  row.at<float>(4) = 1.f;
  for (std::size_t i = 0; i < scores.size(); ++i) row.at<float>(5 + static_cast<int>(i)) = scores[i];
  out.push_back(row);
}

TEST(YoloDecode, ScalesToTheImageAndSuppressesPerClass) {
  cv::Mat a, b;
  AddRow(a, 0.5f, 0.5f, 0.25f, 0.5f, {0.9f, 0.f, 0.f});    // person, centre of a 640x480 image
  AddRow(a, 0.51f, 0.5f, 0.25f, 0.5f, {0.8f, 0.f, 0.7f});  // same person again (suppressed) and a car
  AddRow(b, 0.1f, 0.1f, 0.1f, 0.1f, {0.f, 0.f, 0.35f});    // a car below the threshold
  AddRow(b, 0.2f, 0.2f, 0.1f, 0.1f, {0.2f, 0.f, 0.f});     // a person above the person threshold
  const YoloDecodeParams params{.score_threshold = 0.4f, .person_score_threshold = 0.15f, .nms_threshold = 0.45f};
  const auto d = DecodeYoloOutputs({a, b}, cv::Size(640, 480), kNames, params);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0].class_name, "person");
  EXPECT_FLOAT_EQ(d[0].score, 0.9f);
  EXPECT_NEAR(d[0].box.x, 240, 1e-3);
  EXPECT_NEAR(d[0].box.y, 120, 1e-3);
  EXPECT_NEAR(d[0].box.width, 160, 1e-3);
  EXPECT_NEAR(d[0].box.height, 240, 1e-3);
  EXPECT_EQ(d[1].class_id, 0);
  EXPECT_FLOAT_EQ(d[1].score, 0.2f);
  EXPECT_EQ(d[2].class_id, 2);  // overlaps the person but is another class
  EXPECT_EQ(d[2].class_name, "car");
}

TEST(YoloDecode, ClipsBoxesToTheImage) {
  cv::Mat out;
  AddRow(out, 0.0f, 0.95f, 0.2f, 0.2f, {0.9f, 0.f, 0.f});
  AddRow(out, -0.5f, 0.5f, 0.2f, 0.2f, {0.f, 0.9f, 0.f});  // wholly outside: dropped
  const auto d = DecodeYoloOutputs({out}, cv::Size(100, 200), kNames, YoloDecodeParams{});
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NEAR(d[0].box.x, 0, 1e-4);
  EXPECT_NEAR(d[0].box.width, 10, 1e-4);
  EXPECT_NEAR(d[0].box.y, 170, 1e-3);
  EXPECT_NEAR(d[0].box.y + d[0].box.height, 200, 1e-3);
}

TEST(YoloDecode, IgnoresRowsThatAreNotNumbersOrNotBoxes) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  cv::Mat out;
  AddRow(out, nan, 0.5f, 0.2f, 0.2f, {0.9f, 0.f, 0.f});
  AddRow(out, 0.5f, 0.5f, inf, 0.2f, {0.9f, 0.f, 0.f});
  AddRow(out, 0.5f, 0.5f, -0.2f, 0.2f, {0.9f, 0.f, 0.f});  // a negative width
  AddRow(out, 0.5f, 0.5f, 0.2f, 0.2f, {nan, 0.f, 0.f});
  AddRow(out, 0.5f, 0.5f, 0.2f, 0.2f, {0.f, 7.f, 0.f});     // a score above 1
  AddRow(out, 0.3f, 0.3f, 0.2f, 0.2f, {0.f, 0.f, 0.9f});    // the one good box
  const auto d = DecodeYoloOutputs({out}, cv::Size(100, 100), kNames, YoloDecodeParams{});
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].class_name, "car");
}

TEST(YoloDecode, IgnoresOutputsOfTheWrongShape) {
  const cv::Mat narrow(4, 6, CV_32F, cv::Scalar(1));
  EXPECT_TRUE(DecodeYoloOutputs({narrow, cv::Mat()}, cv::Size(10, 10), kNames, YoloDecodeParams{}).empty());
}

}  // namespace
}  // namespace sgslam
