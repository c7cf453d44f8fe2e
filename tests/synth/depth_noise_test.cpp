// The Kinect-like depth sensor of the synthetic sequences against the exact depth
// it is made from: noise of the modelled size, disparity steps, range limits and
// the projector's shadows.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "sgslam/common/error.h"
#include "sgslam/synth/sequence.h"

namespace sgslam::synth {
namespace {

constexpr double kFocalBaselineSteps = 580.0 * 0.075 * 8;  // f b in 1/8 px steps, as the model quantises

TEST(SynthDepthNoise, SigmaGrowsWithDistanceAndIncidence) {
  EXPECT_NEAR(KinectDepthSigma(1.0, 0), 0.0012 + 0.0019 * 0.36, 1e-12);
  EXPECT_NEAR(KinectDepthSigma(4.0, 0), 0.0258, 1e-4);
  EXPECT_GT(KinectDepthSigma(2.0, 1.2), 1.1 * KinectDepthSigma(2.0, 0.3));
  EXPECT_EQ(ParseDepthNoise("kinect"), DepthNoise::kKinect);
  EXPECT_EQ(ParseDepthNoise("none"), DepthNoise::kNone);
  EXPECT_THROW(ParseDepthNoise("tof"), InputError);
}

TEST(SynthDepthNoise, NoiseOfTheModelledSizeOnTheDisparityGrid) {
  const SynthSequence seq("loop", 1, 10, 0, DepthNoise::kKinect);
  const RenderedFrame f = seq.Render(0);
  double sum = 0, sum2 = 0;
  int n = 0, valid = 0, outliers = 0, off_grid = 0;
  for (int y = 0; y < f.depth.rows; ++y) {
    for (int x = 0; x < f.depth.cols; ++x) {
      const double z = f.depth.at<float>(y, x), m = f.depth_raw.at<std::uint16_t>(y, x) / kDepthFactor;
      if (m == 0) continue;
      ++valid;
      EXPECT_GE(m, 0.5);
      EXPECT_LE(m, 5.0);
      const double step = z * z / kFocalBaselineSteps;
      outliers += std::abs(m - z) > 5 * KinectDepthSigma(z, 1.4) + step;
      const double steps = kFocalBaselineSteps / m;  // whole numbers, up to the 0.2 mm of the PNG
      off_grid += std::abs(steps - std::round(steps)) > 0.05;
      if (z < 1.8 || z > 2.2) continue;
      sum += m - z;
      sum2 += (m - z) * (m - z);
      ++n;
    }
  }
  ASSERT_GT(n, 1000);
  const double mean = sum / n, std = std::sqrt(sum2 / n - mean * mean);
  const double expected = std::hypot(KinectDepthSigma(2.0, 0.7), 4.0 / kFocalBaselineSteps / std::sqrt(12.0));
  std::printf("at 1.8-2.2 m: error %.4f +- %.4f m (model %.4f) over %d pixels; %d valid\n", mean, std, expected, n,
              valid);
  EXPECT_LT(std::abs(mean), 0.002);
  EXPECT_NEAR(std, expected, 0.3 * expected);
  EXPECT_EQ(outliers, 0);
  EXPECT_EQ(off_grid, 0);
}

// Pixels without depth where the exact depth is within range: in the shadow of a
// nearer surface to their right.
TEST(SynthDepthNoise, ShadowsFallLeftOfNearerSurfaces) {
  const SynthSequence seq("loop", 1, 10, 0, DepthNoise::kKinect);
  const RenderedFrame f = seq.Render(0);
  int shadowed = 0;
  for (int y = 0; y < f.depth.rows; ++y) {
    for (int x = 0; x + 1 < f.depth.cols; ++x) {
      const float z = f.depth.at<float>(y, x);
      if (f.depth_raw.at<std::uint16_t>(y, x) != 0 || z < 0.7 || z > 4.5) continue;
      bool nearer = false;
      for (int r = x + 1; r < std::min(x + 80, f.depth.cols) && !nearer; ++r)
        nearer = f.depth.at<float>(y, r) < 0.99f * z;
      const Quad& q = f.surfaces[f.surface.at<int>(y, x)];
      const double facing =
          std::abs((f.T_w_c.rotation().transpose() * q.normal()).dot(seq.intrinsics().Ray(x, y).normalized()));
      if (facing < 0.2) continue;  // grazing: no depth for that reason
      EXPECT_TRUE(nearer) << x << ", " << y;
      ++shadowed;
    }
  }
  std::printf("%d shadowed pixels\n", shadowed);
  EXPECT_GT(shadowed, 200);
}

TEST(SynthDepthNoise, DeterministicPerFrameAndExactWithoutNoise) {
  const SynthSequence noisy("loop", 1, 10, 0, DepthNoise::kKinect), exact("loop", 1, 10);
  const cv::Mat a = noisy.Render(3).depth_raw, b = noisy.Render(3).depth_raw;
  EXPECT_EQ(cv::countNonZero(a != b), 0);
  const RenderedFrame e = exact.Render(3);
  cv::Mat rounded, diff;
  e.depth.convertTo(rounded, CV_16U, kDepthFactor);
  cv::absdiff(e.depth_raw, rounded, diff);
  EXPECT_EQ(cv::countNonZero(diff > 1), 0);
  EXPECT_GT(cv::countNonZero(a != e.depth_raw), static_cast<int>(a.total() / 2));
}

}  // namespace
}  // namespace sgslam::synth
