// Usage: object_truth_tool <tum_seq_dir> pt <frame> <u> <v>... | box <frame> <u0> <v0> <u1> <v1> [<dmin> <dmax> [<zmin> <zmax>]] | ray <frame> <z_plane> <u> <v>... | proj <frame> <x> <y> <z> | vis <points.txt> | grid <frame> <out.png>
//
// Helper used to build tests/data/tum_fr1_rpy_objects.json (see docs/object-truth-tum_fr1_rpy.md).
// Frames are indices into associations.txt. World = groundtruth.txt frame (T_w_c interpolated at the rgb timestamp).
//   pt    world point of pixels (depth = median of valid depth in a 5x5 window; pixel undistorted first)
//   box   back-project all valid pixels of a box, optionally gated by camera depth and world height;
//         prints the median point ("med"), the middle of the 2nd..98th percentile extent ("mid") and that extent
//   ray   where a pixel's ray meets the horizontal plane z = z_plane (for surfaces without depth)
//   proj  pixel, expected depth and measured depth of a world point
//   vis   for lines "name x y z" (a name may repeat), the frame ranges where any of the name's points projects
//         inside the image and is not hidden (measured depth not closer than expected - max(0.15 m, 8 %))
//   grid  write the rgb frame with a 40 px grid, for reading pixel coordinates
// Build: g++ -O2 object_truth_tool.cpp $(pkg-config --cflags --libs opencv4) -I/usr/include/eigen3
#include <Eigen/Geometry>
#include <opencv2/opencv.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Pair { double t_rgb; std::string rgb; double t_depth; std::string depth; };
struct Pose { double t; Eigen::Vector3d p; Eigen::Quaterniond q; };

const cv::Matx33d K(517.3, 0, 318.6, 0, 516.5, 255.3, 0, 0, 1);  // TUM freiburg1
const cv::Vec<double, 5> kDist(0.2624, -0.9531, -0.0054, 0.0026, 1.1633);

std::vector<Pair> readAssociations(const std::string& file) {
  std::vector<Pair> out;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    Pair p;
    s >> p.t_rgb >> p.rgb >> p.t_depth >> p.depth;
    out.push_back(p);
  }
  return out;
}

std::vector<Pose> readGroundTruth(const std::string& file) {
  std::vector<Pose> out;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    Pose p;
    double qx, qy, qz, qw;
    s >> p.t >> p.p.x() >> p.p.y() >> p.p.z() >> qx >> qy >> qz >> qw;
    p.q = Eigen::Quaterniond(qw, qx, qy, qz).normalized();
    out.push_back(p);
  }
  return out;
}

// T_w_c at time t, interpolated between the bracketing samples; false if they are more than 50 ms apart.
bool poseAt(const std::vector<Pose>& gt, double t, Eigen::Isometry3d& T) {
  auto it = std::lower_bound(gt.begin(), gt.end(), t, [](const Pose& a, double b) { return a.t < b; });
  if (it == gt.begin() || it == gt.end()) return false;
  const Pose& a = *(it - 1);
  const Pose& b = *it;
  if (b.t - a.t > 0.05) return false;
  const double s = (t - a.t) / (b.t - a.t);
  T.setIdentity();
  T.linear() = a.q.slerp(s, b.q).toRotationMatrix();
  T.translation() = (1 - s) * a.p + s * b.p;
  return true;
}

Eigen::Vector3d rayOf(double u, double v) {  // undistorted ray with z = 1 in the camera frame
  std::vector<cv::Point2d> in{{u, v}}, out;
  cv::undistortPoints(in, out, K, kDist);
  return {out[0].x, out[0].y, 1.0};
}

bool project(const Eigen::Vector3d& c, int& u, int& v) {  // camera-frame point -> distorted pixel
  if (c.z() <= 0.1) return false;
  std::vector<cv::Point3d> in{{c.x(), c.y(), c.z()}};
  std::vector<cv::Point2d> out;
  cv::projectPoints(in, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, kDist, out);
  u = static_cast<int>(std::lround(out[0].x));
  v = static_cast<int>(std::lround(out[0].y));
  return true;
}

double depthAt(const cv::Mat& d, int u, int v, int r) {  // median valid depth (m) in a (2r+1)^2 window, 0 if none
  std::vector<double> z;
  for (int y = v - r; y <= v + r; ++y)
    for (int x = u - r; x <= u + r; ++x)
      if (x >= 0 && y >= 0 && x < d.cols && y < d.rows && d.at<uint16_t>(y, x) > 0) z.push_back(d.at<uint16_t>(y, x) / 5000.0);
  if (z.empty()) return 0;
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  return z[z.size() / 2];
}

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * (v.size() - 1) + 0.5))];
}

int visibility(const std::string& dir, const std::vector<Pair>& frames, const std::vector<Pose>& gt, const char* pointsFile) {
  std::vector<std::string> names;
  std::vector<Eigen::Vector3d> points;
  std::ifstream in(pointsFile);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string name;
    double x, y, z;
    if (s >> name >> x >> y >> z) { names.push_back(name); points.emplace_back(x, y, z); }
  }
  std::vector<std::string> objects;
  for (const auto& n : names)
    if (std::find(objects.begin(), objects.end(), n) == objects.end()) objects.push_back(n);
  std::vector<std::vector<bool>> seen(objects.size(), std::vector<bool>(frames.size(), false));
  for (size_t k = 0; k < frames.size(); ++k) {
    Eigen::Isometry3d T;
    if (!poseAt(gt, frames[k].t_rgb, T)) continue;
    const cv::Mat d = cv::imread(dir + "/" + frames[k].depth, cv::IMREAD_UNCHANGED);
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d c = T.inverse() * points[i];
      int u, v;
      if (!project(c, u, v) || u < 8 || v < 8 || u >= d.cols - 8 || v >= d.rows - 8) continue;
      const double z = depthAt(d, u, v, 3);
      if (z > 0 && z < c.z() - std::max(0.15, 0.08 * c.z())) continue;  // something closer hides it
      seen[std::find(objects.begin(), objects.end(), names[i]) - objects.begin()][k] = true;
    }
  }
  for (size_t o = 0; o < objects.size(); ++o) {  // ranges, bridging gaps of up to 8 frames
    std::string ranges;
    int start = -1, last = -100, count = 0, first300 = 0;
    for (int k = 0; k < static_cast<int>(frames.size()); ++k) {
      if (!seen[o][k]) continue;
      ++count;
      if (k < 300) ++first300;
      if (start >= 0 && k - last > 8) {
        ranges += std::to_string(start) + "-" + std::to_string(last) + ", ";
        start = k;
      }
      if (start < 0) start = k;
      last = k;
    }
    if (start >= 0) ranges += std::to_string(start) + "-" + std::to_string(last);
    std::printf("%s|%d|%d|%s\n", objects[o].c_str(), count, first300, ranges.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: see the comment at the top of object_truth_tool.cpp\n");
    return 2;
  }
  const std::string dir = argv[1], mode = argv[2];
  const auto frames = readAssociations(dir + "/associations.txt");
  const auto gt = readGroundTruth(dir + "/groundtruth.txt");
  if (mode == "vis") return visibility(dir, frames, gt, argv[3]);

  const int k = std::atoi(argv[3]);
  if (k < 0 || k >= static_cast<int>(frames.size())) {
    std::fprintf(stderr, "frame %d out of range\n", k);
    return 2;
  }
  if (mode == "grid" && argc > 4) {
    cv::Mat im = cv::imread(dir + "/" + frames[k].rgb);
    for (int x = 0; x < im.cols; x += 40) cv::line(im, {x, 0}, {x, im.rows}, cv::Scalar(0, 255, 255), 1);
    for (int y = 0; y < im.rows; y += 40) cv::line(im, {0, y}, {im.cols, y}, cv::Scalar(0, 255, 255), 1);
    for (int x = 0; x < im.cols; x += 80)
      for (int y = 0; y < im.rows; y += 80)
        cv::putText(im, std::to_string(x) + "," + std::to_string(y), {x + 2, y + 12}, cv::FONT_HERSHEY_PLAIN, 0.8, cv::Scalar(0, 0, 255));
    return cv::imwrite(argv[4], im) ? 0 : 1;
  }
  Eigen::Isometry3d T;
  if (!poseAt(gt, frames[k].t_rgb, T)) {
    std::printf("%d no ground-truth pose at t=%.6f\n", k, frames[k].t_rgb);
    return 1;
  }
  const cv::Mat d = cv::imread(dir + "/" + frames[k].depth, cv::IMREAD_UNCHANGED);

  if (mode == "pt") {
    for (int i = 4; i + 1 < argc; i += 2) {
      const int u = std::atoi(argv[i]), v = std::atoi(argv[i + 1]);
      const double z = depthAt(d, u, v, 2);
      if (z <= 0) {
        std::printf("%d %d %d nodepth\n", k, u, v);
        continue;
      }
      const Eigen::Vector3d w = T * (rayOf(u, v) * z);
      std::printf("%d %d %d z=%.3f  %.3f %.3f %.3f\n", k, u, v, z, w.x(), w.y(), w.z());
    }
  } else if (mode == "ray" && argc > 4) {
    const double zPlane = std::atof(argv[4]);
    for (int i = 5; i + 1 < argc; i += 2) {
      const int u = std::atoi(argv[i]), v = std::atoi(argv[i + 1]);
      const Eigen::Vector3d o = T.translation(), dirW = T.linear() * rayOf(u, v);
      const double s = (zPlane - o.z()) / dirW.z();
      const Eigen::Vector3d w = o + s * dirW;
      std::printf("%d %d %d range=%.3f  %.3f %.3f %.3f\n", k, u, v, s * dirW.norm(), w.x(), w.y(), w.z());
    }
  } else if (mode == "proj" && argc > 6) {
    const Eigen::Vector3d c = T.inverse() * Eigen::Vector3d(std::atof(argv[4]), std::atof(argv[5]), std::atof(argv[6]));
    int u = -1, v = -1;
    const bool inside = project(c, u, v) && u >= 0 && v >= 0 && u < d.cols && v < d.rows;
    std::printf("%d proj u=%d v=%d expected_z=%.3f measured_z=%.3f\n", k, u, v, c.z(), inside ? depthAt(d, u, v, 3) : -1.0);
  } else if (mode == "box" && argc > 7) {
    const int u0 = std::atoi(argv[4]), v0 = std::atoi(argv[5]), u1 = std::atoi(argv[6]), v1 = std::atoi(argv[7]);
    const double dMin = argc > 9 ? std::atof(argv[8]) : 0, dMax = argc > 9 ? std::atof(argv[9]) : 0;  // 0 0: median +-0.25 m
    const double zMin = argc > 11 ? std::atof(argv[10]) : -1e9, zMax = argc > 11 ? std::atof(argv[11]) : 1e9;
    std::vector<Eigen::Vector3d> P;
    std::vector<double> depths;
    for (int v = std::max(0, v0); v <= std::min(d.rows - 1, v1); ++v)
      for (int u = std::max(0, u0); u <= std::min(d.cols - 1, u1); ++u) {
        const double z = d.at<uint16_t>(v, u) / 5000.0;
        if (z <= 0 || (dMax > 0 && (z < dMin || z > dMax))) continue;
        const Eigen::Vector3d w = T * (rayOf(u, v) * z);
        if (w.z() < zMin || w.z() > zMax) continue;
        P.push_back(w);
        depths.push_back(z);
      }
    if (P.empty()) {
      std::printf("%d box: no depth\n", k);
      return 1;
    }
    const double zMed = percentile(depths, 0.5);
    std::vector<double> X, Y, Z;
    for (size_t i = 0; i < P.size(); ++i)
      if (dMax > 0 || std::fabs(depths[i] - zMed) < 0.25) {
        X.push_back(P[i].x());
        Y.push_back(P[i].y());
        Z.push_back(P[i].z());
      }
    const double lo[3] = {percentile(X, .02), percentile(Y, .02), percentile(Z, .02)};
    const double hi[3] = {percentile(X, .98), percentile(Y, .98), percentile(Z, .98)};
    std::printf("%d box n=%zu zmed=%.3f med %.3f %.3f %.3f mid %.3f %.3f %.3f lo %.3f %.3f %.3f hi %.3f %.3f %.3f\n", k, X.size(), zMed,
                percentile(X, .5), percentile(Y, .5), percentile(Z, .5), (lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2,
                lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  } else {
    std::fprintf(stderr, "unknown mode or missing arguments: %s\n", mode.c_str());
    return 2;
  }
  return 0;
}
