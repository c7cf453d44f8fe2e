#include "sgslam/eval/plot.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "sgslam/common/error.h"
#include "sgslam/io/atomic_write.h"

namespace sgslam::eval {

namespace {

namespace fs = std::filesystem;

const cv::Scalar kBlack(0, 0, 0), kGtColour(70, 70, 70), kFrameColour(150, 150, 150);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr int kLeft = 80, kRight = 170, kTop = 64, kBottom = 60;  // margins, px

void Text(cv::Mat& img, const std::string& s, cv::Point at, double scale = 0.45) {
  cv::putText(img, s, at, kFont, scale, kBlack, 1, cv::LINE_AA);
}

std::string Metres(double v, double step) {
  const int decimals = std::clamp(static_cast<int>(-std::floor(std::log10(step))), 0, 4);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// 1, 2 or 5 times a power of ten, close to range / 5: readable ticks and scale bar.
double NiceStep(double range) {
  const double raw = std::max(range, 1e-6) / 5.0;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * p >= raw) return m * p;
  }
  return 10.0 * p;
}

// Rows of the result project world positions onto the gt's two main directions.
Eigen::Matrix<double, 2, 3> PrincipalPlane(const Trajectory& gt, Eigen::Vector3d* centroid) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const StampedPose& p : gt) c += p.T_w_c.translation();
  c /= static_cast<double>(gt.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const StampedPose& p : gt) cov += (p.T_w_c.translation() - c) * (p.T_w_c.translation() - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);  // eigenvalues ascending
  Eigen::Matrix<double, 2, 3> P;
  P.row(0) = eig.eigenvectors().col(2).transpose();
  P.row(1) = eig.eigenvectors().col(1).transpose();
  // Eigenvector signs are arbitrary; fix them so the same input always looks the same.
  for (int r = 0; r < 2; ++r) {
    Eigen::Index k = 0;
    P.row(r).cwiseAbs().maxCoeff(&k);
    if (P(r, k) < 0) P.row(r) *= -1.0;
  }
  *centroid = c;
  return P;
}

cv::Scalar JetColour(const cv::Mat& lut, double fraction) {
  const int i = std::clamp(static_cast<int>(std::lround(fraction * 255.0)), 0, 255);
  const cv::Vec3b c = lut.at<cv::Vec3b>(i, 0);
  return cv::Scalar(c[0], c[1], c[2]);
}

void EnsureFolder(const fs::path& path) {
  const fs::path parent = path.parent_path();
  std::error_code ec;
  if (parent.empty() || fs::is_directory(parent, ec)) return;
  fs::create_directories(parent, ec);
  if (ec) throw InputError("cannot create the folder for plot " + path.string() + ": " + ec.message());
}

// The plot area: metres on the ground truth's principal plane to pixels, equal aspect.
struct PlotArea {
  int w = 0, h = 0;  // px, inside the margins
  Eigen::Vector2d mid = Eigen::Vector2d::Zero();
  double scale = 1;  // px per metre
  double step = 1;   // m, tick spacing

  PlotArea(const AtePlotOptions& options, const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b)
      : w(options.width - kLeft - kRight), h(options.height - kTop - kBottom) {
    Eigen::Vector2d lo = a[0], hi = a[0];
    for (const auto* pts : {&a, &b}) {
      for (const Eigen::Vector2d& q : *pts) {
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
    }
    mid = 0.5 * (lo + hi);
    const Eigen::Vector2d range = (hi - lo).cwiseMax(1e-3) * 1.08;
    scale = std::min(w / range.x(), h / range.y());
    step = NiceStep(std::max(w, h) / scale);
  }
  cv::Point Px(const Eigen::Vector2d& q) const {
    return cv::Point(static_cast<int>(std::lround(kLeft + w / 2.0 + (q.x() - mid.x()) * scale)),
                     static_cast<int>(std::lround(kTop + h / 2.0 - (q.y() - mid.y()) * scale)));
  }
};

// Ticks on the frame, in metres from the ground-truth centroid, and the axis names.
void DrawAxes(cv::Mat& img, const PlotArea& a, const AtePlotOptions& options) {
  for (double v = std::ceil((a.mid.x() - a.w / 2.0 / a.scale) / a.step) * a.step; a.Px({v, 0}).x <= kLeft + a.w;
       v += a.step) {
    const int x = a.Px({v, 0}).x;
    cv::line(img, {x, kTop + a.h}, {x, kTop + a.h + 5}, kBlack);
    Text(img, Metres(v, a.step), {x - 15, kTop + a.h + 20}, 0.4);
  }
  for (double v = std::ceil((a.mid.y() - a.h / 2.0 / a.scale) / a.step) * a.step; a.Px({0, v}).y >= kTop;
       v += a.step) {
    const int y = a.Px({0, v}).y;
    cv::line(img, {kLeft - 5, y}, {kLeft, y}, kBlack);
    Text(img, Metres(v, a.step), {kLeft - 55, y + 4}, 0.4);
  }
  cv::rectangle(img, cv::Rect(kLeft, kTop, a.w, a.h), kFrameColour);
  Text(img, "principal axis 1 of ground truth [m]", {kLeft + a.w / 2 - 140, options.height - 12});
  Text(img, "axis 2 [m]", {4, kTop - 12});
}

// The scale bar (bottom left) and the legend (top left), inside the frame.
void DrawScaleAndLegend(cv::Mat& img, const PlotArea& a, const cv::Mat& lut) {
  const cv::Point bar0(kLeft + 15, kTop + a.h - 15);
  const cv::Point bar1(bar0.x + static_cast<int>(std::lround(a.step * a.scale)), bar0.y);
  cv::line(img, bar0, bar1, kBlack, 3);
  Text(img, Metres(a.step, a.step) + " m", {bar0.x, bar0.y - 8});
  cv::rectangle(img, {kLeft + 10, kTop + 10, 260, 46}, cv::Scalar(255, 255, 255), cv::FILLED);
  cv::rectangle(img, {kLeft + 10, kTop + 10, 260, 46}, kFrameColour);
  cv::line(img, {kLeft + 20, kTop + 25}, {kLeft + 50, kTop + 25}, kGtColour, 2, cv::LINE_AA);
  Text(img, "ground truth", {kLeft + 58, kTop + 29});
  cv::line(img, {kLeft + 20, kTop + 45}, {kLeft + 35, kTop + 45}, JetColour(lut, 0.1), 2, cv::LINE_AA);
  cv::line(img, {kLeft + 35, kTop + 45}, {kLeft + 50, kTop + 45}, JetColour(lut, 0.9), 2, cv::LINE_AA);
  Text(img, "estimate (aligned), by error", {kLeft + 58, kTop + 49});
}

// The colour bar of the error, on the right, 0 at the bottom.
void DrawColourBar(cv::Mat& img, const PlotArea& a, const AtePlotOptions& options, const cv::Mat& lut,
                   double max_err) {
  const int cb_x = options.width - kRight + 30;
  for (int y = 0; y < a.h; ++y) {
    cv::line(img, {cb_x, kTop + y}, {cb_x + 20, kTop + y}, JetColour(lut, 1.0 - y / double(a.h - 1)));
  }
  cv::rectangle(img, {cb_x, kTop, 21, a.h}, kFrameColour);
  for (int k = 0; k <= 4; ++k) {
    const int y = kTop + a.h - 1 - k * (a.h - 1) / 4;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4f", max_err * k / 4.0);
    cv::line(img, {cb_x + 21, y}, {cb_x + 26, y}, kBlack);
    Text(img, buf, {cb_x + 30, y + 4}, 0.4);
  }
  Text(img, "ATE [m]", {cb_x - 10, kTop - 10});
}

}  // namespace

void WriteAtePlot(const fs::path& path, const Trajectory& gt, const Trajectory& est, const AteResult& ate,
                  const AtePlotOptions& options) {
  EnsureFolder(path);
  if (gt.empty() || ate.pairs.empty()) throw InputError("nothing to plot for " + path.string());
  Eigen::Vector3d c;
  const Eigen::Matrix<double, 2, 3> P = PrincipalPlane(gt, &c);
  std::vector<Eigen::Vector2d> gt_xy, est_xy;
  for (const StampedPose& p : gt) gt_xy.push_back(P * (p.T_w_c.translation() - c));
  for (const auto& ij : ate.pairs) est_xy.push_back(P * (ate.T_gt_est * est[ij.second].T_w_c.translation() - c));
  const PlotArea area(options, gt_xy, est_xy);
  cv::Mat img(options.height, options.width, CV_8UC3, cv::Scalar(255, 255, 255));
  DrawAxes(img, area, options);

  // Ground truth, then the estimate on top of it, segment colour = mean end error.
  cv::Mat gray(256, 1, CV_8UC1), lut;
  for (int i = 0; i < 256; ++i) gray.at<unsigned char>(i, 0) = static_cast<unsigned char>(i);
  cv::applyColorMap(gray, lut, cv::COLORMAP_JET);
  std::vector<cv::Point> gt_px;
  for (const Eigen::Vector2d& q : gt_xy) gt_px.push_back(area.Px(q));
  cv::polylines(img, gt_px, false, kGtColour, 2, cv::LINE_AA);
  const double max_err = std::max(ate.stats.max, 1e-9);
  for (std::size_t k = 0; k < est_xy.size(); ++k) {
    const std::size_t prev = k == 0 ? 0 : k - 1;
    const cv::Scalar colour = JetColour(lut, 0.5 * (ate.errors[prev] + ate.errors[k]) / max_err);
    cv::line(img, area.Px(est_xy[prev]), area.Px(est_xy[k]), colour, 2, cv::LINE_AA);
  }
  DrawScaleAndLegend(img, area, lut);
  DrawColourBar(img, area, options, lut, max_err);
  char title[128];
  std::snprintf(title, sizeof title, "ATE RMSE %.4f m over %zu pairs (top view)", ate.stats.rmse, ate.stats.count);
  cv::putText(img, title, {kLeft, 30}, kFont, 0.65, kBlack, 1, cv::LINE_AA);

  std::vector<unsigned char> png;
  if (!cv::imencode(".png", img, png)) throw Error("cannot encode the plot " + path.string() + " as PNG");
  WriteFileAtomically(path, std::string(png.begin(), png.end()));
}

}  // namespace sgslam::eval
