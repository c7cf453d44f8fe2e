#include "vocab_eval.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "progress.h"
#include "sgslam/camera/camera.h"
#include "sgslam/common/error.h"
#include "sgslam/features/orb_extractor.h"
#include "sgslam/io/tum_dataset.h"
#include "sgslam/system/run_config.h"

namespace sgslam::app {

namespace {

constexpr int kGridStep = 16;         // px between the depth samples of the overlap test
constexpr double kOverlapSame = 0.3;  // a view sharing this share of its points sees the same place
constexpr double kOverlapNone = 0.01; // ... and below this, none of it

struct View {
  Timestamp t = 0;
  SE3 T_w_c;
  std::vector<Eigen::Vector3d> points_c;  // depth samples, camera frame
  vocab::BowVector bow;
};

// The ground-truth pose nearest in time (within 20 ms), or none.
std::optional<SE3> PoseAt(const Trajectory& gt, Timestamp t) {
  const auto it = std::lower_bound(gt.begin(), gt.end(), t, [](const StampedPose& p, Timestamp x) { return p.t < x; });
  const StampedPose* best = nullptr;
  if (it != gt.end()) best = &*it;
  if (it != gt.begin() && (!best || t - std::prev(it)->t < best->t - t)) best = &*std::prev(it);
  if (!best || std::abs(ToSeconds(best->t - t)) > 0.02) return std::nullopt;
  return best->T_w_c;
}

// Share of a's depth samples that b sees (in its image, in front of it).
double Overlap(const View& a, const View& b, const Camera& cam) {
  if (a.points_c.empty()) return 0;
  const SE3 T_b_a = b.T_w_c.Inverse() * a.T_w_c;
  int seen = 0;
  for (const Eigen::Vector3d& p : a.points_c) {
    const Eigen::Vector3d q = T_b_a * p;
    if (q.z() <= 0.1) continue;
    const Eigen::Vector2d uv = cam.Project(q);
    seen += uv.x() >= 0 && uv.y() >= 0 && uv.x() < cam.width() && uv.y() < cam.height();
  }
  return static_cast<double>(seen) / static_cast<double>(a.points_c.size());
}

std::vector<View> ReadViews(const VocabEvalArgs& a, const vocab::Vocabulary& v, Camera& cam_out) {
  const RunConfig rc = ResolveRunConfig(std::nullopt, a.dataset);
  const Config& config = rc.config;
  cam_out = Camera(config.camera);
  const TumDataset data(a.dataset, config.dataset);
  const auto gt_path = data.groundtruth_path();
  if (!gt_path) throw InputError("vocab eval: " + a.dataset + " has no groundtruth.txt");
  const Trajectory gt = ReadTumTrajectory(*gt_path);
  features::OrbExtractor extractor(config.orb);
  std::vector<View> views;
  ProgressBar bar(data.size(), "frames");
  for (std::size_t i = 0; i < data.size(); i += static_cast<std::size_t>(a.every)) {
    const auto pose = PoseAt(gt, data.frames()[i].t_rgb);
    if (!pose) continue;
    const RgbdImages images = data.Load(i, config.camera);
    View view{images.t, *pose, {}, {}};
    for (int y = kGridStep / 2; y < images.depth.rows; y += kGridStep) {
      for (int x = kGridStep / 2; x < images.depth.cols; x += kGridStep) {
        const double d = images.depth.at<std::uint16_t>(y, x) / config.camera.depth_factor;
        if (d > 0.1) view.points_c.push_back(cam_out.Unproject(x, y, d));
      }
    }
    cv::Mat gray;
    cv::cvtColor(images.bgr, gray, cv::COLOR_BGR2GRAY);
    std::vector<cv::KeyPoint> keys;
    cv::Mat descriptors;
    extractor.Extract(gray, keys, descriptors);
    view.bow = v.Transform(descriptors, 0).words;
    views.push_back(std::move(view));
    bar.Update(i + 1, 0);
  }
  return views;
}

}  // namespace

VocabEvalResult EvaluateVocabulary(const VocabEvalArgs& a) {
  if (a.every < 1) throw InputError("--every must be at least 1");
  const vocab::Vocabulary v = vocab::Vocabulary::Load(a.vocabulary);
  Camera cam{CameraConfig{}};
  const std::vector<View> views = ReadViews(a, v, cam);
  VocabEvalResult r;
  r.views = static_cast<int>(views.size());
  for (std::size_t q = 0; q < views.size(); ++q) {
    // The database: views at least min_gap older.
    std::vector<std::pair<double, std::size_t>> ranked;
    bool revisit = false;
    for (std::size_t d = 0; d < q; ++d) {
      if (ToSeconds(views[q].t - views[d].t) < a.min_gap_s) continue;
      ranked.emplace_back(vocab::Score(views[q].bow, views[d].bow), d);
      revisit = revisit || Overlap(views[q], views[d], cam) >= kOverlapSame;
    }
    if (ranked.empty()) continue;
    std::stable_sort(ranked.begin(), ranked.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    ++r.queries;
    const bool wrong = Overlap(views[q], views[ranked[0].second], cam) < kOverlapNone;
    r.false_top1 += wrong;
    if (!revisit) continue;
    ++r.revisits;
    r.false_top1_revisits += wrong;
    const std::size_t top = std::min<std::size_t>(5, ranked.size());
    const bool hit = std::any_of(ranked.begin(), ranked.begin() + static_cast<std::ptrdiff_t>(top),
                                 [&](const auto& c) { return Overlap(views[q], views[c.second], cam) >= kOverlapSame; });
    r.hits_at5 += hit;
  }
  return r;
}

std::string FormatVocabEval(const VocabEvalResult& r) {
  char line[256];
  std::snprintf(line, sizeof(line),
                "views %d, queries %d, revisits %d: recall@5 %.3f, top-1 with no overlap %.3f of the queries, "
                "%.3f of the revisits\n",
                r.views, r.queries, r.revisits, r.revisits > 0 ? static_cast<double>(r.hits_at5) / r.revisits : 0.0,
                r.queries > 0 ? static_cast<double>(r.false_top1) / r.queries : 0.0,
                r.revisits > 0 ? static_cast<double>(r.false_top1_revisits) / r.revisits : 0.0);
  return line;
}

}  // namespace sgslam::app
