#include "sgslam/camera/camera.h"

#include <gtest/gtest.h>

#include "sgslam/camera/presets.h"

namespace sgslam {
namespace {

TEST(Camera, ProjectInvertsUnproject) {
  const Camera cam(CameraConfig{});
  for (double u : {0.0, 100.5, 639.0}) {
    for (double d : {0.3, 2.0, 7.5}) {
      const Eigen::Vector3d p = cam.Unproject(u, 200.25, d);
      EXPECT_NEAR(p.z(), d, 1e-12);
      EXPECT_LT((cam.Project(p) - Eigen::Vector2d(u, 200.25)).norm(), 1e-9);
    }
  }
}

TEST(Camera, UndistortInvertsDistortOverTheWholeImage) {
  // TUM fr1 has strong radial distortion: corners move by tens of pixels.
  const Camera cam(*CameraPreset("tum_fr1"));
  std::vector<cv::Point2f> distorted;
  std::vector<Eigen::Vector2d> truth;
  for (double v = 10; v <= 470; v += 46) {
    for (double u = 10; u <= 630; u += 62) {
      const Eigen::Vector2d undist(u, v);
      const Eigen::Vector2d d = cam.Distort(undist);
      truth.push_back(undist);
      distorted.emplace_back(static_cast<float>(d.x()), static_cast<float>(d.y()));
    }
  }
  const Eigen::Vector2d corner_shift = cam.Distort({10, 10}) - Eigen::Vector2d(10, 10);
  EXPECT_GT(corner_shift.norm(), 5.0);  // the test means something
  cam.Undistort(distorted);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_NEAR(distorted[i].x, truth[i].x(), 2e-3);
    EXPECT_NEAR(distorted[i].y, truth[i].y(), 2e-3);
  }
}

TEST(Camera, NoDistortionLeavesPointsAlone) {
  const Camera cam(*CameraPreset("tum_fr3"));
  EXPECT_FALSE(cam.has_distortion());
  std::vector<cv::Point2f> pts = {{1.5f, 2.5f}, {600.f, 400.f}};
  cam.Undistort(pts);
  EXPECT_FLOAT_EQ(pts[1].x, 600.f);
}

TEST(Camera, DepthFactorConvertsToMetres) {
  const Camera cam(CameraConfig{});
  EXPECT_DOUBLE_EQ(cam.DepthMetres(5000), 1.0);
  EXPECT_DOUBLE_EQ(cam.DepthMetres(0), 0.0);
}

TEST(CameraPresets, FolderNamesPickTheRightCamera) {
  EXPECT_EQ(CameraPresetForFolder("/d/rgbd_dataset_freiburg3_walking_xyz"), "tum_fr3");
  EXPECT_EQ(CameraPresetForFolder("/d/rgbd_dataset_freiburg1_desk/"), "tum_fr1");
  EXPECT_EQ(CameraPresetForFolder("tum_fr2_pioneer"), "tum_fr2");
  EXPECT_EQ(CameraPresetForFolder("/x/rgbd_bonn_crowd"), "bonn");
  EXPECT_EQ(CameraPresetForFolder("/x/my_sequence"), std::nullopt);
  EXPECT_FALSE(CameraPreset("nope"));
}

}  // namespace
}  // namespace sgslam
