#include "sgslam/synth/depth_noise.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "sgslam/common/error.h"
#include "sgslam/synth/random.h"
#include "sgslam/synth/renderer.h"

namespace sgslam::synth {

namespace {

constexpr double kIrFocal = 580.0;                  // px, the Kinect's IR camera
constexpr double kBaseline = 0.075;                 // m, projector to IR camera
constexpr double kSubpixel = 8.0;                   // disparity steps per pixel
constexpr double kMinRange = 0.5, kMaxRange = 5.0;  // m
const double kMaxIncidence = 80.0 * std::numbers::pi / 180;

// Standard normal, near enough: a sum of four uniform 16-bit numbers (Irwin-Hall).
double Gaussian(std::uint64_t h) {
  double sum = 0;
  for (int b = 0; b < 4; ++b) sum += static_cast<double>((h >> (16 * b)) & 0xffff) / 65536.0;
  return (sum - 2.0) * std::sqrt(3.0);  // the sum's variance is 4 / 12
}

// 255 where the projector's light is blocked: a nearer surface at x' > x hides
// pixel x when x' - x < f b (1 / z' - 1 / z), found in one right-to-left sweep.
cv::Mat ShadowMask(const cv::Mat& depth, double fb) {
  cv::Mat shadow(depth.size(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < depth.rows; ++y) {
    const float* z = depth.ptr<float>(y);
    std::uint8_t* out = shadow.ptr<std::uint8_t>(y);
    double reach = 0;  // max over x' > x of 1 / z' - (x' - x) / fb
    for (int x = depth.cols - 2; x >= 0; --x) {
      reach = std::max(reach, z[x + 1] > 0 ? 1.0 / z[x + 1] : 0.0) - 1.0 / fb;
      if (z[x] > 0 && 1.0 / z[x] < reach - 1e-9) out[x] = 255;
    }
  }
  return shadow;
}

// The Kinect's depth (m, 0 = none) of a surface at exact depth z seen at incidence
// theta, with standard normal draw g: noise, then disparity quantisation.
double KinectDepth(double z, double theta, double g) {
  if (theta > kMaxIncidence) return 0;
  const double noisy = z + KinectDepthSigma(z, theta) * g;
  if (noisy <= 0) return 0;
  const double disparity = std::round(kIrFocal * kBaseline / noisy * kSubpixel) / kSubpixel;
  const double measured = disparity > 0 ? kIrFocal * kBaseline / disparity : 0;
  return measured >= kMinRange && measured <= kMaxRange ? measured : 0;
}

}  // namespace

DepthNoise ParseDepthNoise(const std::string& name) {
  if (name == "none") return DepthNoise::kNone;
  if (name == "kinect") return DepthNoise::kKinect;
  throw InputError("unknown depth noise '" + name + "' (choose none or kinect)");
}

const char* DepthNoiseName(DepthNoise noise) { return noise == DepthNoise::kKinect ? "kinect" : "none"; }

double KinectDepthSigma(double z, double theta) {
  const double grazing = theta / (0.5 * std::numbers::pi - theta);
  return 0.0012 + 0.0019 * (z - 0.4) * (z - 0.4) + 0.0001 / std::sqrt(z) * grazing * grazing;
}

cv::Mat KinectDepthRaw(const RenderedFrame& f, const Intrinsics& K, std::uint64_t seed, double depth_factor) {
  const cv::Mat shadow = ShadowMask(f.depth, K.fx * kBaseline);
  const Eigen::Matrix3d R_c_w = f.T_w_c.rotation().transpose();
  std::vector<Eigen::Vector3d> normals_c;
  normals_c.reserve(f.surfaces.size());
  for (const Quad& q : f.surfaces) normals_c.push_back(R_c_w * q.normal());
  const std::uint64_t noise_seed = Mix64(seed ^ 0xd3e7a11c0ffeeULL);  // not the colour noise's
  cv::Mat raw(f.depth.size(), CV_16U, cv::Scalar(0));
  for (int y = 0; y < raw.rows; ++y) {
    const float* z = f.depth.ptr<float>(y);
    const int* surface = f.surface.ptr<int>(y);
    const std::uint8_t* shadowed = shadow.ptr<std::uint8_t>(y);
    std::uint16_t* out = raw.ptr<std::uint16_t>(y);
    for (int x = 0; x < raw.cols; ++x) {
      if (z[x] <= 0 || surface[x] < 0 || shadowed[x]) continue;
      const Eigen::Vector3d ray = K.Ray(x, y).normalized();
      const double theta = std::acos(std::min(1.0, std::abs(normals_c[surface[x]].dot(ray))));
      const double m = KinectDepth(z[x], theta, Gaussian(Hash(noise_seed, f.index, y, x)));
      out[x] = static_cast<std::uint16_t>(std::min(std::round(m * depth_factor), 65535.0));
    }
  }
  return raw;
}

}  // namespace sgslam::synth
