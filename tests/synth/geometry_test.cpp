// The rendered depth against the scene's surfaces, computed independently here by
// brute force (every ray against every surface, no screen rectangles).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "sgslam/common/error.h"
#include "sgslam/synth/sequence.h"

namespace sgslam::synth {
namespace {

struct Hit {
  double z = std::numeric_limits<double>::infinity();  // camera z (the ray has z = 1)
  int quad = -1;
};

Hit CastBruteForce(const std::vector<Quad>& quads_w, const SE3& T_w_c, const Eigen::Vector3d& ray_c) {
  const Eigen::Vector3d dir_w = T_w_c.quaternion() * ray_c;
  Hit best;
  for (int i = 0; i < static_cast<int>(quads_w.size()); ++i) {
    const double t = IntersectRay(quads_w[i], T_w_c.translation(), dir_w);
    if (t > 0 && t < best.z) best = {t, i};
  }
  return best;
}

// Camera z of the pixel centre's ray on the (infinite) plane of a quad.
double PlaneDepth(const Quad& q_w, const SE3& T_w_c, const Eigen::Vector3d& ray_c) {
  const Quad q_c = Transformed(T_w_c.Inverse(), q_w);
  return q_c.normal().dot(q_c.centre) / q_c.normal().dot(ray_c);
}

TEST(SynthGeometry, StaticWorldPointsReprojectOntoTheirDepthInOtherFrames) {
  const SynthSequence seq("static", 3, 120);
  const Intrinsics& K = seq.intrinsics();
  int checked = 0;
  for (int i : {0, 40, 80}) {
    const SE3 T_w_ci = seq.CameraPose(i);
    const std::vector<Quad> quads = seq.scene().SurfacesAt(seq.Seconds(i));
    for (int v = 60; v < K.height; v += 120) {
      for (int u = 80; u < K.width; u += 160) {
        // The known world point: where pixel (u, v) of frame i meets the scene.
        const Eigen::Vector3d ray = K.Ray(u, v);
        const Hit hit = CastBruteForce(quads, T_w_ci, ray);
        ASSERT_GE(hit.quad, 0);
        const Eigen::Vector3d X_w = T_w_ci * (hit.z * ray);
        for (int j : {i, i + 5, i + 20, i + 39}) {
          const RenderedFrame f = seq.Render(j);
          const Eigen::Vector3d X_c = f.T_w_c.Inverse() * X_w;
          if (X_c.z() <= 0.1) continue;
          const int pu = static_cast<int>(std::lround(K.fx * X_c.x() / X_c.z() + K.cx));
          const int pv = static_cast<int>(std::lround(K.fy * X_c.y() / X_c.z() + K.cy));
          if (pu < 0 || pv < 0 || pu >= K.width || pv >= K.height) continue;
          if (f.surface.at<int>(pv, pu) != hit.quad) continue;  // occluded, or off the surface's edge
          const double z_pixel = PlaneDepth(quads[hit.quad], f.T_w_c, K.Ray(pu, pv));
          EXPECT_NEAR(f.depth_raw.at<std::uint16_t>(pv, pu) / kDepthFactor, z_pixel, 0.5 / kDepthFactor + 1e-7);
          EXPECT_NEAR(f.depth.at<float>(pv, pu), z_pixel, 1e-5 * z_pixel);
          // Within half a pixel of the point's own depth (surfaces are planar).
          EXPECT_NEAR(z_pixel, X_c.z(), 0.02 * X_c.z());
          if (j == i && pu == u && pv == v) {
            EXPECT_NEAR(f.depth.at<float>(pv, pu), X_c.z(), 1e-5 * X_c.z());
          }
          ++checked;
        }
      }
    }
  }
  EXPECT_GE(checked, 40);
}

TEST(SynthGeometry, EveryDepthLiesOnItsSurfaceAndIsTheNearestHit) {
  const SynthSequence seq("walkers", 1, 120);
  const Intrinsics& K = seq.intrinsics();
  for (int i : {0, 45, 100}) {
    const RenderedFrame f = seq.Render(i);
    int brute_force_checks = 0;
    for (int v = 0; v < K.height; ++v) {
      for (int u = 0; u < K.width; ++u) {
        const int s = f.surface.at<int>(v, u);
        ASSERT_GE(s, 0) << "the room is closed: every ray hits something";
        const double z = f.depth.at<float>(v, u);
        ASSERT_GT(z, 0.1);
        EXPECT_NEAR(f.depth_raw.at<std::uint16_t>(v, u), z * kDepthFactor, 0.5 + 1e-2);  // z is a float here
        const Eigen::Vector3d p_w = f.T_w_c * (z * K.Ray(u, v));
        const Quad& q = f.surfaces[s];
        ASSERT_NEAR(q.normal().dot(p_w - q.centre), 0, 1e-5) << "pixel " << u << "," << v;
        ASSERT_TRUE(q.Contains(p_w, 1e-5)) << "pixel " << u << "," << v;
        EXPECT_EQ(f.object_id.at<int>(v, u), q.object);
        if ((u + v * K.width) % 11 != 0) continue;
        const Hit hit = CastBruteForce(f.surfaces, f.T_w_c, K.Ray(u, v));
        ASSERT_NEAR(hit.z, z, 1e-6 * z) << "pixel " << u << "," << v << " frame " << i;
        ++brute_force_checks;
      }
    }
    EXPECT_GT(brute_force_checks, 20000);
  }
}

// With a readout time, row v is seen from the camera at the frame's time + (v /
// height - 1/2) * readout (the model of camera/rolling_shutter.h): each row's
// depth and surface are those of a brute-force cast from that row's own pose; the
// middle row is the global-shutter frame's, the others are not.
TEST(SynthGeometry, RollingShutterRowsAreSeenFromTheirOwnCameras) {
  constexpr double kReadout = 0.03;
  const SynthSequence rolling("static", 3, 60, kReadout);
  const SynthSequence global("static", 3, 60);
  const Intrinsics& K = rolling.intrinsics();
  for (int i : {10, 50}) {
    const RenderedFrame f = rolling.Render(i);
    const RenderedFrame g = global.Render(i);
    EXPECT_TRUE(f.T_w_c.translation() == g.T_w_c.translation()) << "the frame's pose is its middle row's";
    int checks = 0, differ = 0;
    for (int v = 0; v < K.height; v += 7) {
      const double s = (static_cast<double>(v) / K.height - 0.5) * kReadout;
      const SE3 T_w_row = rolling.scene().camera.Pose(rolling.Seconds(i) + s);
      for (int u = 3; u < K.width; u += 13) {
        const Hit hit = CastBruteForce(f.surfaces, T_w_row, K.Ray(u, v));
        ASSERT_EQ(f.surface.at<int>(v, u), hit.quad) << "pixel " << u << "," << v << " frame " << i;
        ASSERT_NEAR(f.depth.at<float>(v, u), hit.z, 1e-6 * hit.z) << "pixel " << u << "," << v;
        differ += std::abs(f.depth.at<float>(v, u) - g.depth.at<float>(v, u)) > 1e-4f;
        ++checks;
      }
    }
    const int mid = K.height / 2;
    EXPECT_EQ(cv::countNonZero(f.depth.row(mid) != g.depth.row(mid)), 0) << "the middle row is exposed at the frame's time";
    EXPECT_GT(differ, checks / 4) << "the camera moves during the readout: most rows see another view";
  }
  EXPECT_THROW(SynthSequence("static", 3, 10, -0.01), InputError);
  EXPECT_THROW(SynthSequence("static", 3, 10, 0.05), InputError) << "longer than a frame time";
}

TEST(SynthGeometry, CameraStaysInsideTheRoomAndMovesLikeAHandheldCamera) {
  for (const char* preset : {"static", "walkers", "degenerate", "objects"}) {
    const SynthSequence seq(preset, 1, 300);
    const Eigen::Vector3d room = seq.scene().room_size;
    double max_speed = 0, max_rate_deg = 0, sum_speed = 0;
    for (int i = 0; i + 1 < seq.size(); ++i) {
      const SE3 a = seq.CameraPose(i), b = seq.CameraPose(i + 1);
      ASSERT_TRUE((a.translation().array() > 0.3).all() && (a.translation().array() < room.array() - 0.3).all())
          << preset << " frame " << i;
      const double dt = seq.Seconds(i + 1) - seq.Seconds(i);
      const double speed = (b.translation() - a.translation()).norm() / dt;
      sum_speed += speed;
      max_speed = std::max(max_speed, speed);
      max_rate_deg = std::max(max_rate_deg, a.quaternion().angularDistance(b.quaternion()) / dt * 180 / std::numbers::pi);
    }
    const double mean_speed = sum_speed / (seq.size() - 1);
    EXPECT_GT(mean_speed, 0.1) << preset;
    EXPECT_LT(max_speed, 0.6) << preset;
    EXPECT_LT(max_rate_deg, 40) << preset;
    std::printf("%-10s camera: mean %.2f m/s, max %.2f m/s, max %.1f deg/s\n", preset, mean_speed, max_speed,
                max_rate_deg);
  }
}

}  // namespace
}  // namespace sgslam::synth
