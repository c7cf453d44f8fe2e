#include "sgslam/synth/renderer.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "sgslam/synth/random.h"

namespace sgslam::synth {

namespace {

constexpr double kBlurSigma = 0.6;   // px
constexpr float kNoiseSigma = 1.5f;  // intensity

// Fixed light from above; shading is constant per surface, so image brightness of a
// point does not change with the viewpoint (brightness constancy for optical flow).
float LightFactor(const Quad& q_w) {
  static const Eigen::Vector3d kLight = Eigen::Vector3d(0.35, 0.5, 1.0).normalized();
  const double c = q_w.normal().dot(kLight);
  return static_cast<float>(0.55 + 0.45 * (q_w.two_sided ? std::abs(c) : std::max(c, 0.0)));
}

// quads_c: the surfaces in the camera frame (global shutter), or empty with
// T_w_c_rows, one camera per row (rolling shutter): the hit is then found on the
// world quad, the texture being a function of the surface coordinates alone.
cv::Mat Shade(const Scene& scene, const std::vector<Quad>& quads_w, const std::vector<Quad>& quads_c,
              const std::vector<SE3>& T_w_c_rows, const RayCastResult& hits, const Intrinsics& K) {
  std::vector<float> light(quads_w.size());
  for (std::size_t i = 0; i < quads_w.size(); ++i) light[i] = LightFactor(quads_w[i]);
  cv::Mat bgr(K.height, K.width, CV_8UC3, cv::Scalar::all(0));
  for (int y = 0; y < K.height; ++y) {
    const int* surface = hits.surface.ptr<int>(y);
    const double* depth = hits.depth.data() + static_cast<std::size_t>(y) * K.width;
    cv::Vec3b* out = bgr.ptr<cv::Vec3b>(y);
    for (int x = 0; x < K.width; ++x) {
      const int qi = surface[x];
      if (qi < 0) continue;
      const Eigen::Vector3d p_c = depth[x] * K.Ray(x, y);
      const Eigen::Vector2d st = quads_c.empty() ? quads_w[qi].SurfaceCoordinates(T_w_c_rows[y] * p_c)
                                                 : quads_c[qi].SurfaceCoordinates(p_c);
      const Quad& q = quads_w[qi];
      float c[3];
      SampleTexture(scene.textures[q.texture], st.x(), st.y(), c);
      for (int k = 0; k < 3; ++k) out[x][k] = cv::saturate_cast<uchar>(c[k] * light[qi]);
    }
  }
  return bgr;
}

// Gaussian noise from one hash per pixel: a sum of four uniform 5-bit numbers
// (Irwin-Hall) per channel is close enough to Gaussian and identical everywhere.
void AddNoise(cv::Mat& bgr, std::uint64_t seed, int frame_index) {
  constexpr float kScale = kNoiseSigma / 18.466f;  // std of a sum of 4 uniform 0..31
  for (int y = 0; y < bgr.rows; ++y) {
    cv::Vec3b* row = bgr.ptr<cv::Vec3b>(y);
    for (int x = 0; x < bgr.cols; ++x) {
      const std::uint64_t h = Hash(seed, frame_index, y, x);
      for (int k = 0; k < 3; ++k) {
        int sum = 0;
        for (int b = 0; b < 4; ++b) sum += static_cast<int>((h >> (20 * k + 5 * b)) & 31);
        row[x][k] = cv::saturate_cast<uchar>(row[x][k] + kScale * static_cast<float>(sum - 62));
      }
    }
  }
}

void FillObjectImages(const Scene& scene, RenderedFrame& f, const std::vector<double>& depth) {
  const int h = f.surface.rows, w = f.surface.cols;
  f.depth = cv::Mat(h, w, CV_32F, cv::Scalar(0));
  f.depth_raw = cv::Mat(h, w, CV_16U, cv::Scalar(0));
  f.object_id = cv::Mat(h, w, CV_32S, cv::Scalar(0));
  f.dynamic_mask = cv::Mat(h, w, CV_8U, cv::Scalar(0));
  std::vector<VisibleObject> visible(scene.objects.size() + 1);
  long dynamic = 0;
  for (int y = 0; y < h; ++y) {
    const int* surface = f.surface.ptr<int>(y);
    for (int x = 0; x < w; ++x) {
      if (surface[x] < 0) continue;
      const double z = depth[static_cast<std::size_t>(y) * w + x];
      f.depth.at<float>(y, x) = static_cast<float>(z);
      const double raw = std::round(z * kDepthFactor);
      f.depth_raw.at<std::uint16_t>(y, x) = raw < 65535 ? static_cast<std::uint16_t>(raw) : 0;
      const int id = f.surfaces[surface[x]].object;
      f.object_id.at<int>(y, x) = id;
      if (id == 0) continue;
      VisibleObject& v = visible[static_cast<std::size_t>(id)];
      v.box = v.pixels == 0 ? cv::Rect(x, y, 1, 1) : (v.box | cv::Rect(x, y, 1, 1));
      v.id = id;
      ++v.pixels;
      if (scene.IsDynamic(id)) {
        f.dynamic_mask.at<std::uint8_t>(y, x) = 255;
        ++dynamic;
      }
    }
  }
  for (const VisibleObject& v : visible) {
    if (v.pixels > 0) f.visible.push_back(v);
  }
  f.dynamic_fraction = static_cast<double>(dynamic) / (static_cast<double>(w) * h);
}

}  // namespace

RenderedFrame RenderFrame(const Scene& scene, const Intrinsics& K, const SE3& T_w_c, double t_seconds,
                          int frame_index, std::uint64_t noise_seed, const std::vector<SE3>& T_w_c_rows) {
  RenderedFrame f;
  f.index = frame_index;
  f.T_w_c = T_w_c;
  f.surfaces = scene.SurfacesAt(t_seconds);
  std::vector<Quad> quads_c;
  RayCastResult hits;
  if (T_w_c_rows.empty()) {
    const SE3 T_c_w = T_w_c.Inverse();
    quads_c.reserve(f.surfaces.size());
    for (const Quad& q : f.surfaces) quads_c.push_back(Transformed(T_c_w, q));
    hits = RayCast(quads_c, K);
  } else {
    std::vector<SE3> T_c_w_rows;
    T_c_w_rows.reserve(T_w_c_rows.size());
    for (const SE3& T : T_w_c_rows) T_c_w_rows.push_back(T.Inverse());
    hits = RayCastRows(f.surfaces, T_c_w_rows, K);
  }
  f.surface = hits.surface;
  f.bgr = Shade(scene, f.surfaces, quads_c, T_w_c_rows, hits, K);
  cv::GaussianBlur(f.bgr, f.bgr, cv::Size(5, 5), kBlurSigma, kBlurSigma, cv::BORDER_REFLECT);
  AddNoise(f.bgr, noise_seed, frame_index);
  FillObjectImages(scene, f, hits.depth);
  return f;
}

}  // namespace sgslam::synth
