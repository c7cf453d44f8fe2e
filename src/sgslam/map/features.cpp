#include "sgslam/map/features.h"

#include <algorithm>
#include <stdexcept>

#include "sgslam/camera/rolling_shutter.h"

namespace sgslam {

namespace {

// Moves keys_un and depth to the middle-row camera of a frame turning at
// angular_velocity (from the one they were corrected with), then derives
// u_right and the grid from them.
void Correct(Features& f, const Eigen::Vector3d& angular_velocity) {
  CorrectRollingShutter(*f.camera, f.keys, f.angular_velocity, angular_velocity, f.keys_un, f.depth);
  if (f.camera->config().readout > 0) f.angular_velocity = angular_velocity;  // a global shutter: nothing moved
  f.u_right.assign(f.size(), -1.0f);
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (f.depth[i] > 0) f.u_right[i] = static_cast<float>(f.keys_un[i].pt.x - f.camera->baseline_fx() / f.depth[i]);
  }
  f.grid = FeatureGrid(f.keys_un, f.bounds);
}

}  // namespace

ImageBounds UndistortedBounds(const Camera& camera) {
  const float w = static_cast<float>(camera.width()), h = static_cast<float>(camera.height());
  if (!camera.has_distortion()) return {0.0, w, 0.0, h};
  std::vector<cv::Point2f> corners = {{0, 0}, {w, 0}, {0, h}, {w, h}};
  camera.Undistort(corners);
  return {std::min(corners[0].x, corners[2].x), std::max(corners[1].x, corners[3].x),
          std::min(corners[0].y, corners[1].y), std::max(corners[2].y, corners[3].y)};
}

std::shared_ptr<const Features> MakeFeatures(std::vector<cv::KeyPoint> keys, cv::Mat descriptors,
                                             const cv::Mat& depth_raw, std::shared_ptr<const Camera> camera,
                                             std::shared_ptr<const ScaleLevels> scale,
                                             std::vector<std::uint8_t> dynamic, std::vector<Detection> detections,
                                             std::vector<std::uint8_t> unjudged,
                                             const Eigen::Vector3d& angular_velocity) {
  auto f = std::make_shared<Features>();
  f->bounds = UndistortedBounds(*camera);
  f->keys = std::move(keys);
  f->descriptors = std::move(descriptors);
  const std::size_t n = f->keys.size();

  std::vector<cv::Point2f> pts(n);
  for (std::size_t i = 0; i < n; ++i) pts[i] = f->keys[i].pt;
  camera->Undistort(pts);
  f->keys_un = f->keys;
  for (std::size_t i = 0; i < n; ++i) f->keys_un[i].pt = pts[i];

  f->depth.assign(n, -1.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const int u = cvRound(f->keys[i].pt.x), v = cvRound(f->keys[i].pt.y);
    if (u < 0 || v < 0 || u >= depth_raw.cols || v >= depth_raw.rows) continue;
    const double d = camera->DepthMetres(depth_raw.at<std::uint16_t>(v, u));
    if (d > 0) f->depth[i] = static_cast<float>(d);
  }
  f->camera = std::move(camera);
  Correct(*f, angular_velocity);  // from zero: raw keypoints
  if (!dynamic.empty() && dynamic.size() != n) throw std::invalid_argument("MakeFeatures: one dynamic label per keypoint");
  f->dynamic = std::move(dynamic);
  if (!unjudged.empty() && unjudged.size() != n) throw std::invalid_argument("MakeFeatures: one unjudged flag per keypoint");
  f->unjudged = std::move(unjudged);
  f->detections = std::move(detections);
  f->scale = std::move(scale);
  return f;
}

std::shared_ptr<const Features> WithRollingShutterCorrection(const Features& f, const Eigen::Vector3d& angular_velocity) {
  auto out = std::make_shared<Features>(f);
  Correct(*out, angular_velocity);
  return out;
}

}  // namespace sgslam
