#include "sgslam/semantic/objects.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include <Eigen/Eigenvalues>

#include "sgslam/common/stats.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/semantic/background_planes.h"
#include "sgslam/semantic/object_sizes.h"

namespace sgslam {

namespace {

// Share of the detection box (centred) whose depths give the object's depth: the
// box's border holds background and neighbours (Sec. III-E; the release's value).
constexpr double kObjectBoxShrink = 0.6;
// 3-D IoU above which an observation joins an object of its class (besides a
// centre inside the other's box): low, views of one object from different sides
// overlap little, and objects of one class rarely touch.
constexpr double kObjectMergeIou = 0.1;
// Depths further than this many MADs from an object's median are outliers.
constexpr double kMadFactor = 3.0;
// Association boxes are grown by this for the centre-inside test.
constexpr double kMergeMargin = 0.1;  // m
// Share of the samples cut off at each end of each axis of an object's extent: a
// thin leg or a pot's base is a small share of the samples.
constexpr double kExtentTrim = 0.01;
// Background planes: the ring around the box they are fitted in (share of the box
// size; wide enough to hold both walls of a corner), the distance counted as on a
// plane (plus a term in depth^2: 2-3 sigma of Kinect noise), and the share of the
// box's points above which a plane is the object's own face and stays.
constexpr double kRing = 0.3;
constexpr double kPlaneTolerance = 0.01;            // m
constexpr double kPlaneToleranceQuadratic = 0.002;  // 1/m
constexpr double kPlaneMaxShare = 0.8;
// An observation with more of its samples on movers than this is a mover's.
constexpr double kObjectMaxMovingShare = 0.5;

double Volume(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  const Eigen::Vector3d d = (max - min).cwiseMax(0.0);
  return d.x() * d.y() * d.z();
}

bool Inside(const Eigen::Vector3d& p, const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
}

// Floor and walls continue outside the box; fitted there, their points inside
// the box are dropped (see background_planes.h).
void RemoveBackgroundPlanes(const cv::Rect2f& b, const cv::Rect& full, const cv::Mat& depth_raw, double depth_factor,
                            const PixelRays& rays, const SemanticConfig& config, int max_planes, double depth,
                            std::vector<Eigen::Vector3f>& points) {
  const cv::Rect image(0, 0, depth_raw.cols, depth_raw.rows);
  const int mx = std::max(6, static_cast<int>(std::lround(b.width * kRing)));
  const int my = std::max(6, static_cast<int>(std::lround(b.height * kRing)));
  const cv::Rect outer = cv::Rect(full.x - mx, full.y - my, full.width + 2 * mx, full.height + 2 * my) & image;
  const int ring_area = outer.area() - full.area();
  if (ring_area <= 0) return;
  const int step = std::max(1, static_cast<int>(std::sqrt(ring_area / (2.0 * kObjectMaxPoints))));
  std::vector<Eigen::Vector3f> ring;
  for (int v = outer.y; v < outer.y + outer.height; v += step) {
    const std::uint16_t* d = depth_raw.ptr<std::uint16_t>(v);
    for (int u = outer.x; u < outer.x + outer.width; u += step) {
      if (full.contains(cv::Point(u, v)) || d[u] == 0) continue;
      const double z = d[u] / depth_factor;
      if (z < config.depth_min || z > config.depth_max) continue;
      const cv::Vec2f& r = rays.at(u, v);
      ring.emplace_back(r[0] * static_cast<float>(z), r[1] * static_cast<float>(z), static_cast<float>(z));
    }
  }
  PlaneFitOptions options;
  options.max_planes = max_planes;
  options.tolerance =
      static_cast<float>(kPlaneTolerance + kPlaneToleranceQuadratic * depth * depth);
  for (const Plane& plane : FitPlanes(ring, options)) {
    std::vector<Eigen::Vector3f> kept;
    kept.reserve(points.size());
    for (const auto& p : points)
      if (!OnPlane(plane, p, options)) kept.push_back(p);
    const double removed = static_cast<double>(points.size() - kept.size());
    if (removed > kPlaneMaxShare * static_cast<double>(points.size())) continue;
    if (static_cast<int>(kept.size()) < kObjectMinPoints) continue;
    points.swap(kept);
  }
}

bool InBox(const cv::Point& p, const cv::Rect2f& b) {
  return p.x >= b.x && p.y >= b.y && p.x < b.x + b.width && p.y < b.y + b.height;
}

bool InAnyBox(const cv::Point& p, const std::vector<cv::Rect2f>& boxes) {
  return std::any_of(boxes.begin(), boxes.end(), [&](const cv::Rect2f& b) { return InBox(p, b); });
}

cv::Rect PixelBox(const cv::Rect2f& b, double share, const cv::Rect& image) {
  return cv::Rect(cv::Point(cvRound(b.x + b.width * (1 - share) / 2), cvRound(b.y + b.height * (1 - share) / 2)),
                  cv::Point(cvRound(b.x + b.width * (1 + share) / 2), cvRound(b.y + b.height * (1 + share) / 2))) &
         image;
}

// Depth samples (about 4 * max_points) of a pixel rectangle, in range.
void SampleDepths(const cv::Mat& depth_raw, double depth_factor, const cv::Rect& r, int max_points,
                  const SemanticConfig& config, std::vector<cv::Point>& pixels, std::vector<double>& depths) {
  if (r.area() <= 0) return;
  const int step = std::max(1, static_cast<int>(std::sqrt(r.area() / (4.0 * max_points))));
  for (int v = r.y; v < r.y + r.height; v += step) {
    const std::uint16_t* d = depth_raw.ptr<std::uint16_t>(v);
    for (int u = r.x; u < r.x + r.width; u += step) {
      const double z = d[u] / depth_factor;
      if (d[u] == 0 || z < config.depth_min || z > config.depth_max) continue;
      pixels.emplace_back(u, v);
      depths.push_back(z);
    }
  }
}

// The inner samples' depths outside every box in `others`, or all of them when
// fewer than min_points are left.
std::vector<double> UncoveredDepths(const std::vector<cv::Point>& pixels, const std::vector<double>& depths,
                                    const std::vector<cv::Rect2f>& others, int min_points) {
  if (others.empty()) return depths;
  std::vector<double> out;
  for (std::size_t i = 0; i < pixels.size(); ++i)
    if (!InAnyBox(pixels[i], others)) out.push_back(depths[i]);
  return static_cast<int>(out.size()) >= min_points ? out : depths;
}

// Robust spread around `centre`: 1.4826 MAD, at least 1 cm (a flat face has MAD ~ 0).
double Mad(const std::vector<double>& values, double centre) {
  std::vector<double> dev(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) dev[i] = std::abs(values[i] - centre);
  return std::max(Median(dev) * 1.4826, 0.01);
}

// 3-D outliers: points much further from the median point than the others.
void DropOutliers(double mad_factor, std::vector<Eigen::Vector3f>& points) {
  if (points.size() < 3) return;
  Eigen::Vector3f m;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> c;
    c.reserve(points.size());
    for (const auto& p : points) c.push_back(p[a]);
    m[a] = static_cast<float>(Median(c));
  }
  std::vector<double> dist;
  dist.reserve(points.size());
  for (const auto& p : points) dist.push_back((p - m).norm());
  const double dm = Median(dist);
  const double limit = dm + mad_factor * Mad(dist, dm);
  std::vector<Eigen::Vector3f> kept;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (dist[i] <= limit) kept.push_back(points[i]);
  }
  points.swap(kept);
}

// Even thinning to at most max_points, deterministic.
void Thin(int max_points, std::vector<Eigen::Vector3f>& points) {
  if (static_cast<int>(points.size()) <= max_points) return;
  std::vector<Eigen::Vector3f> thin;
  const double stride = static_cast<double>(points.size()) / max_points;
  for (int k = 0; k < max_points; ++k) thin.push_back(points[static_cast<std::size_t>(k * stride)]);
  points.swap(thin);
}

}  // namespace

std::vector<double> ObjectDepths(const std::vector<Detection>& detections, const cv::Mat& depth_raw,
                                 double depth_factor, const SemanticConfig& config) {
  std::vector<double> out(detections.size(), 0.0);
  if (depth_raw.empty() || depth_raw.type() != CV_16UC1) return out;
  const cv::Rect image(0, 0, depth_raw.cols, depth_raw.rows);
  for (std::size_t i = 0; i < detections.size(); ++i) {
    std::vector<cv::Rect2f> others;
    for (std::size_t j = 0; j < detections.size(); ++j)
      if (j != i) others.push_back(detections[j].box);
    std::vector<cv::Point> pixels;
    std::vector<double> depths;
    SampleDepths(depth_raw, depth_factor, PixelBox(detections[i].box, kObjectBoxShrink, image),
                 kObjectMaxPoints, config, pixels, depths);
    const std::vector<double> own = UncoveredDepths(pixels, depths, others, kObjectMinPoints);
    if (!own.empty()) out[i] = Median(own);
  }
  return out;
}

std::optional<ObjectObservation> ObserveObject(const Detection& detection, const cv::Mat& depth_raw,
                                               double depth_factor, const PixelRays& rays,
                                               const SemanticConfig& config, const std::vector<OtherBox>& others,
                                               const cv::Mat& movers, const ObserveObjectOptions& options) {
  if (depth_raw.empty() || depth_raw.type() != CV_16UC1 || depth_raw.size() != rays.size()) return std::nullopt;
  const cv::Rect image(0, 0, depth_raw.cols, depth_raw.rows);
  const cv::Rect2f& b = detection.box;
  const cv::Rect full = PixelBox(b, 1.0, image);
  // Sec. III-E: the box is first reduced (its border holds background and
  // neighbours) and the depth of the object is taken there...
  const cv::Rect inner = PixelBox(b, kObjectBoxShrink, image);
  if (inner.area() <= 0 || full.area() <= 0) return std::nullopt;
  std::vector<OtherBox> overlapping;  // with a known depth
  std::vector<cv::Rect2f> other_boxes;
  for (const OtherBox& o : others) {
    if (o.depth > 0 && (o.box & b).area() > 0) {
      overlapping.push_back(o);
      other_boxes.push_back(o.box);
    }
  }
  std::vector<cv::Point> inner_pixels;
  std::vector<double> inner_depths;
  SampleDepths(depth_raw, depth_factor, inner, kObjectMaxPoints, config, inner_pixels, inner_depths);
  if (static_cast<int>(inner_depths.size()) < kObjectMinPoints) return std::nullopt;
  // ... away from the other boxes where possible: a chair half behind a table
  // would take the table's depth.
  const std::vector<double> own = UncoveredDepths(inner_pixels, inner_depths, other_boxes, kObjectMinPoints);
  const double median = Median(own);
  const double mad = Mad(own, median);
  // ... then every depth of the original box is compared with it, and rejected
  // when too far (median / MAD: robust where the paper takes the mean), or
  // further than a share of the box's width at that depth (kObjectDepthBandWidth).
  const int row = full.y + full.height / 2;
  const double width_m = std::abs(rays.at(full.x + full.width - 1, row)[0] - rays.at(full.x, row)[0]) * median;
  const double band = std::max(kMadFactor * mad, options.depth_band_width * width_m);
  std::vector<cv::Point> pixels;
  std::vector<double> depths;
  SampleDepths(depth_raw, depth_factor, full, 2 * kObjectMaxPoints, config, pixels, depths);
  std::vector<Eigen::Vector3f> points;
  int moving = 0;
  const bool has_movers = !movers.empty() && movers.size() == depth_raw.size() && movers.type() == CV_8UC1;
  for (std::size_t i = 0; i < depths.size(); ++i) {
    if (std::abs(depths[i] - median) > band) continue;
    // Movers never become map objects: their pixels are left out, and an object
    // mostly on them (carried, or a mover the detector named otherwise) is none.
    if (has_movers && movers.at<std::uint8_t>(pixels[i]) != 0) {
      ++moving;
      continue;
    }
    // Where another box covers the pixel, it goes to the object whose depth is nearer.
    const bool theirs = std::any_of(overlapping.begin(), overlapping.end(), [&](const OtherBox& o) {
      return InBox(pixels[i], o.box) && std::abs(depths[i] - o.depth) < std::abs(depths[i] - median);
    });
    if (theirs) continue;
    const cv::Vec2f& r = rays.at(pixels[i].x, pixels[i].y);
    const auto z = static_cast<float>(depths[i]);
    points.emplace_back(r[0] * z, r[1] * z, z);
  }
  if (moving > kObjectMaxMovingShare * static_cast<double>(moving + points.size())) return std::nullopt;
  if (options.background_planes > 0) {
    RemoveBackgroundPlanes(b, full, depth_raw, depth_factor, rays, config, options.background_planes, median, points);
  }
  DropOutliers(kMadFactor, points);
  if (static_cast<int>(points.size()) < kObjectMinPoints) return std::nullopt;
  Thin(kObjectMaxPoints, points);
  ObjectObservation o;
  o.class_id = detection.class_id;
  o.class_name = detection.class_name;
  o.score = detection.score;
  o.box = detection.box;
  o.points_c = std::move(points);
  return o;
}

namespace {

// Association voxels: a few centimetres, so that a keyboard's samples and the
// desk's beneath it, or two monitors side by side, share few voxels.
constexpr double kAssociationVoxel = 0.05;  // m
// Two sets of samples of one class are one object when their boxes overlap
// (kObjectMergeIou, or a centre inside the other's box) or this share of the
// smaller one's voxels is in the other's.
constexpr double kSameClassOverlap = 0.3;
// Of different classes (the detector named one object twice: a monitor and a
// laptop), they must overlap much more, and the smaller must cover a fair share of
// the larger: a keyboard's samples lie on a table's box, not the other way round.
constexpr double kOtherClassOverlap = 0.5;
constexpr double kOtherClassCover = 0.2;
// A keyframe's pose that moved less than this since an object's geometry was made
// does not remake it.
constexpr double kRefreshTranslation = 0.01;  // m
constexpr double kRefreshRotation = 0.005;    // rad
// Carving checks each sample against at most this many other views (evenly
// chosen): an object seen from 60 keyframes costs no more than one seen from 12.
constexpr int kCarveViews = 12;
// The views' bookkeeping: samples of an object projected into a keyframe, how
// many of them must land in the image for it to be in view, and how many with a
// depth to judge it. A depth within kViewDepthTolerance (or its share of the
// distance) of a sample, or nearer by up to the object's extent, is the object;
// nearer still, something in front of it; further, the keyframe sees through
// where it was.
constexpr int kViewSamples = 64;
constexpr double kViewInImage = 0.5;
constexpr int kViewMinDepths = 8;
constexpr double kViewDepthTolerance = 0.10;  // m
constexpr double kViewDepthShare = 0.05;
constexpr double kViewSeenShare = 0.5;     // of the depths: the object is there
constexpr double kViewMissingShare = 0.6;  // of the depths: seen through
constexpr double kViewMaxMoving = 0.1;     // of the samples in the image: on a mover

std::int64_t VoxelKey(const Eigen::Vector3d& p) {
  const auto c = [](double v) { return static_cast<std::int64_t>(std::floor(v / kAssociationVoxel)) & 0x1FFFFF; };
  return (c(p.x()) << 42) | (c(p.y()) << 21) | c(p.z());
}

std::vector<std::int64_t> Voxels(const std::vector<Eigen::Vector3d>& points) {
  std::vector<std::int64_t> v;
  v.reserve(points.size());
  for (const auto& p : points) v.push_back(VoxelKey(p));
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

std::size_t Common(const std::vector<std::int64_t>& a, const std::vector<std::int64_t>& b) {
  std::size_t n = 0;
  for (std::size_t i = 0, j = 0; i < a.size() && j < b.size();) {
    if (a[i] < b[j]) {
      ++i;
    } else if (b[j] < a[i]) {
      ++j;
    } else {
      ++n, ++i, ++j;
    }
  }
  return n;
}

struct Geometry {
  const std::vector<std::int64_t>& voxels;
  const Eigen::Vector3d& min;
  const Eigen::Vector3d& max;
};

// How strongly two sets of samples are one object (the larger the better), or a
// negative value when they are not: see the constants above.
double Affinity(const Geometry& a, const Geometry& b, bool same_class) {
  if (a.voxels.empty() || b.voxels.empty()) return -1;
  const double common = static_cast<double>(Common(a.voxels, b.voxels));
  const double small = common / static_cast<double>(std::min(a.voxels.size(), b.voxels.size()));
  const double large = common / static_cast<double>(std::max(a.voxels.size(), b.voxels.size()));
  if (!same_class) return small >= kOtherClassOverlap && large >= kOtherClassCover ? small + large : -1;
  const Eigen::Vector3d lo = a.min.cwiseMax(b.min), hi = a.max.cwiseMin(b.max);
  const double inter = Volume(lo, hi);
  const double iou = inter / std::max(Volume(a.min, a.max) + Volume(b.min, b.max) - inter, 1e-12);
  // A partial first view gives a small box: a centre inside the other box counts too.
  const Eigen::Vector3d m = Eigen::Vector3d::Constant(kMergeMargin);
  const bool nested = Inside((a.min + a.max) / 2, b.min - m, b.max + m) || Inside((b.min + b.max) / 2, a.min - m, a.max + m);
  if (iou <= kObjectMergeIou && !nested && small < kSameClassOverlap) return -1;
  return 1.0 + iou + (nested ? 1.0 : 0.0) + small;
}

bool Moved(const SE3& a, const SE3& b) {
  const SE3 d = a.Inverse() * b;
  return d.translation().norm() > kRefreshTranslation || so3::Log(d.quaternion()).norm() > kRefreshRotation;
}

// Extents along the samples' principal axes (trimmed like BoxOf), longest first:
// a size that does not depend on how the map frame is turned.
Eigen::Vector3d PrincipalExtents(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 3) return Eigen::Vector3d::Zero();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  Eigen::Vector3d out;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> c;
    c.reserve(points.size());
    for (const auto& p : points) c.push_back(solver.eigenvectors().col(a).dot(p - mean));
    out[a] = Percentile(c, 1.0 - kExtentTrim) - Percentile(c, kExtentTrim);
  }
  std::sort(out.data(), out.data() + 3, std::greater<>());
  return out;
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

}  // namespace

ObjectDatabase::Box ObjectDatabase::BoxOf(const std::vector<Eigen::Vector3d>& points) {
  Box b{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  if (points.empty()) return b;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> c;
    c.reserve(points.size());
    for (const auto& p : points) c.push_back(p[a]);
    b.min[a] = Percentile(c, kExtentTrim);
    b.max[a] = Percentile(c, 1.0 - kExtentTrim);
  }
  return b;
}

ObjectDatabase::ClassVote ObjectDatabase::WinningClass(const Object& o) {
  std::vector<std::pair<std::pair<int, std::string>, double>> votes;
  double total = 0;
  for (const ObjectObservation& obs : o.observations) {
    // Every detection counts, a weak one too (its score is its weight).
    const double w = std::max(static_cast<double>(obs.score), 1e-3);
    total += w;
    const std::pair<int, std::string> key{obs.class_id, obs.class_name};
    auto it = std::find_if(votes.begin(), votes.end(), [&](const auto& v) { return v.first == key; });
    if (it == votes.end()) {
      votes.push_back({key, w});
    } else {
      it->second += w;
    }
  }
  ClassVote best;
  double best_sum = -1;
  for (const auto& [key, sum] : votes) {  // the first of equal sums: the one seen first
    if (sum > best_sum) {
      best = {key.first, key.second, 0};
      best_sum = sum;
    }
  }
  best.share = total > 0 ? best_sum / total : 0;
  return best;
}

void ObjectDatabase::Rebuild(Object& o) const {
  o.points_w.clear();
  for (std::size_t i = 0; i < o.observations.size(); ++i) {
    for (const auto& p : o.observations[i].points_c) o.points_w.push_back(o.T_w_c[i] * p.cast<double>());
  }
  o.voxels = Voxels(o.points_w);
  o.box = o.observations.size() > 1 ? BoxOf(CarvedPoints(o, o.T_w_c)) : BoxOf(o.points_w);
}

ObjectDatabase::Object* ObjectDatabase::Associate(const std::vector<std::int64_t>& voxels, const Box& box,
                                                  const ObjectObservation& observation) {
  Object* best = nullptr;
  double best_score = 0;
  for (Object& o : objects_) {
    const ClassVote c = WinningClass(o);
    const bool same = c.class_id == observation.class_id && c.class_name == observation.class_name;
    const double score = Affinity({voxels, box.min, box.max}, {o.voxels, o.box.min, o.box.max}, same);
    if (score > best_score) {
      best = &o;
      best_score = score;
    }
  }
  return best;
}

int ObjectDatabase::Add(ObjectObservation observation, const SE3& T_w_c) {
  std::vector<Eigen::Vector3d> world;
  world.reserve(observation.points_c.size());
  for (const auto& p : observation.points_c) world.push_back(T_w_c * p.cast<double>());
  Object* o = Associate(Voxels(world), BoxOf(world), observation);
  if (o == nullptr) {
    o = &objects_.emplace_back();
    o->id = next_id_++;
  }
  observation.T_w_c_added = T_w_c;
  o->observations.push_back(std::move(observation));
  o->T_w_c.push_back(T_w_c);
  Rebuild(*o);
  return o->id;
}

void ObjectDatabase::Refresh(const KeyFramePoseFn& pose_of) {
  for (Object& o : objects_) {
    bool moved = false;
    for (std::size_t i = 0; i < o.observations.size(); ++i) {
      if (!o.observations[i].keyframe) continue;
      const SE3 T = pose_of(*o.observations[i].keyframe);
      if (Moved(T, o.T_w_c[i])) {
        o.T_w_c[i] = T;
        moved = true;
      }
    }
    if (moved) Rebuild(o);
  }
  MergeOverlapping();
}

void ObjectDatabase::MergeOverlapping() {
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t a = 0; a < objects_.size() && !merged; ++a) {
      for (std::size_t b = a + 1; b < objects_.size() && !merged; ++b) {
        Object& x = objects_[a];
        Object& y = objects_[b];
        const ClassVote cx = WinningClass(x), cy = WinningClass(y);
        const bool same = cx.class_id == cy.class_id && cx.class_name == cy.class_name;
        if (Affinity({x.voxels, x.box.min, x.box.max}, {y.voxels, y.box.min, y.box.max}, same) < 0) continue;
        // The older object (smaller id) takes the other's views and counts.
        for (std::size_t i = 0; i < y.observations.size(); ++i) {
          x.observations.push_back(std::move(y.observations[i]));
          x.T_w_c.push_back(y.T_w_c[i]);
        }
        x.views_expected = std::max(x.views_expected, y.views_expected);
        x.views_seen = std::max(x.views_seen, y.views_seen);
        x.missing = std::min(x.missing, y.missing);
        Rebuild(x);
        objects_.erase(objects_.begin() + static_cast<std::ptrdiff_t>(b));
        merged = true;
      }
    }
  }
}

int ObjectDatabase::CountViews(const std::vector<int>& joined, const SE3& T_w_c, const cv::Mat& depth_raw,
                               double depth_factor, const cv::Mat& movers) {
  if (depth_raw.empty() || depth_raw.type() != CV_16UC1 || !project_) return 0;
  const SE3 T_c_w = T_w_c.Inverse();
  const bool has_movers = !movers.empty() && movers.size() == depth_raw.size() && movers.type() == CV_8UC1;
  int removed = 0;
  for (auto it = objects_.begin(); it != objects_.end();) {
    Object& o = *it;
    if (std::find(joined.begin(), joined.end(), o.id) != joined.end()) {
      ++o.views_expected;
      ++o.views_seen;
      o.missing = 0;
      ++it;
      continue;
    }
    int sampled = 0, in_image = 0, there = 0, through = 0, depths = 0, moving = 0;
    // A depth nearer than a sample by up to the object's own extent is its front
    // (the sample is on a side another view saw), not something in front of it.
    const double own = (o.box.max - o.box.min).maxCoeff();
    const std::size_t step = std::max<std::size_t>(1, o.points_w.size() / kViewSamples);
    for (std::size_t k = 0; k < o.points_w.size(); k += step) {
      ++sampled;
      const Eigen::Vector3d p_c = T_c_w * o.points_w[k];
      if (p_c.z() < config_.depth_min) continue;
      const Eigen::Vector2d uv = project_(p_c);
      const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
      if (u < 0 || v < 0 || u >= depth_raw.cols || v >= depth_raw.rows) continue;
      ++in_image;
      if (has_movers && movers.at<std::uint8_t>(v, u) != 0) ++moving;
      const std::uint16_t raw = depth_raw.at<std::uint16_t>(v, u);
      if (raw == 0) continue;
      ++depths;
      const double d = raw / depth_factor - p_c.z();
      const double tolerance = std::max(kViewDepthTolerance, kViewDepthShare * p_c.z());
      if (d <= tolerance && d >= -own - tolerance) {
        ++there;
      } else if (d > tolerance) {
        ++through;
      }
    }
    // A mover over or beside it disturbs the view (and the detector): it says nothing.
    const bool in_view = sampled > 0 && in_image >= kViewInImage * sampled && depths >= kViewMinDepths &&
                         moving <= kViewMaxMoving * in_image;
    if (in_view && there >= kViewSeenShare * depths) {
      ++o.views_expected;  // there and in view, but not detected
      o.missing = 0;
    } else if (in_view && through >= kViewMissingShare * depths) {
      ++o.missing;
    }
    if (o.missing >= kObjectMissingViews) {
      it = objects_.erase(it);
      ++removed;
    } else {
      ++it;
    }
  }
  return removed;
}

void ObjectDatabase::Restore(std::vector<Object> objects, int next_id) {
  objects_ = std::move(objects);
  next_id_ = next_id;
  for (Object& o : objects_) {
    o.T_w_c.clear();
    for (const ObjectObservation& obs : o.observations) o.T_w_c.push_back(obs.T_w_c_added);
    Rebuild(o);
  }
}

bool ObjectDatabase::Complete(const Object& o) {
  return std::any_of(o.observations.begin(), o.observations.end(), [](const ObjectObservation& ob) { return !ob.cut; });
}

std::vector<Eigen::Vector3d> ObjectDatabase::CarvedPoints(const Object& o, const std::vector<SE3>& T_w_c) const {
  const std::size_t n = o.observations.size();
  std::vector<SE3> T_c_w(n);
  for (std::size_t j = 0; j < n; ++j) T_c_w[j] = T_w_c[j].Inverse();
  const std::size_t stride = std::max<std::size_t>(1, (n + kCarveViews - 1) / kCarveViews);
  std::vector<Eigen::Vector3d> all, kept;
  // Views cut by the image border shape the box only while no whole view exists:
  // their segmentation lacks the background ring on the cut side and drags in
  // floor or wall.
  const bool drop_cut = Complete(o);
  for (std::size_t i = 0; i < n; ++i) {
    if (drop_cut && o.observations[i].cut) continue;
    for (const auto& p : o.observations[i].points_c) {
      const Eigen::Vector3d x = T_w_c[i] * p.cast<double>();
      all.push_back(x);
      int in = 0, out = 0;
      for (std::size_t j = i % stride; j < n && project_; j += stride) {
        if (j == i) continue;
        const Eigen::Vector3d p_c = T_c_w[j] * x;
        if (p_c.z() < config_.depth_min * 0.5) continue;
        const Eigen::Vector2d uv = project_(p_c);
        if (uv.x() < 0 || uv.y() < 0 || uv.x() >= image_.width || uv.y() >= image_.height) continue;
        const cv::Rect2f& b = o.observations[j].box;
        const bool inside = uv.x() >= b.x && uv.y() >= b.y && uv.x() <= b.x + b.width && uv.y() <= b.y + b.height;
        (inside ? in : out)++;
      }
      if (in >= out) kept.push_back(x);
    }
  }
  // Views that disagree about everything (a bad merge, a wrong pose): keep all.
  return kept.size() * 2 >= all.size() ? kept : all;
}

std::vector<ObjectEstimate> ObjectDatabase::Estimate(const KeyFramePoseFn& pose_of, const SE3& T_out_w) const {
  std::vector<ObjectEstimate> out;
  out.reserve(objects_.size());
  for (const Object& o : objects_) {
    std::vector<SE3> T_w_c;
    double score = 0;
    std::vector<const KeyFrame*> keyframes;
    for (const ObjectObservation& obs : o.observations) {
      T_w_c.push_back(obs.keyframe ? pose_of(*obs.keyframe) : obs.T_w_c_added);
      score += obs.score;
      if (obs.keyframe) keyframes.push_back(obs.keyframe.get());
    }
    std::sort(keyframes.begin(), keyframes.end());
    const auto distinct = static_cast<int>(std::unique(keyframes.begin(), keyframes.end()) - keyframes.begin());
    const int unanchored = static_cast<int>(std::count_if(o.observations.begin(), o.observations.end(),
                                                          [](const ObjectObservation& obs) { return !obs.keyframe; }));
    std::vector<Eigen::Vector3d> points_w = CarvedPoints(o, T_w_c);
    std::vector<Eigen::Vector3d> points = points_w;
    for (auto& p : points) p = T_out_w * p;
    const Box b = BoxOf(points);
    const ClassVote c = WinningClass(o);
    ObjectEstimate e;
    e.id = o.id;
    e.class_id = c.class_id;
    e.class_name = c.class_name;
    e.class_share = c.share;
    e.observations = distinct + unanchored;
    e.views_expected = o.views_expected;
    e.views_seen = o.views_seen;
    e.points = static_cast<int>(points.size());
    const double mean_score = o.observations.empty() ? 0.0 : score / static_cast<double>(o.observations.size());
    e.confidence = mean_score * (1.0 - std::exp(-e.observations / 2.0));
    e.centroid = (b.min + b.max) / 2;
    e.size = b.max - b.min;
    e.dimensions = PrincipalExtents(points_w);
    e.complete = Complete(o);
    // The viewpoint change: the object's direction in the cameras (where in the
    // image it was) and from the object to the cameras (the baseline).
    const Box box_w = BoxOf(points_w);
    const Eigen::Vector3d centre_w = (box_w.min + box_w.max) / 2;
    std::vector<Eigen::Vector3d> in_camera, from_object;
    for (const SE3& T : T_w_c) {
      in_camera.push_back(T.Inverse() * centre_w);
      from_object.push_back(T.translation() - centre_w);
    }
    for (std::size_t i = 0; i < T_w_c.size(); ++i) {
      for (std::size_t j = i + 1; j < T_w_c.size(); ++j) {
        e.spread_deg = std::max({e.spread_deg, AngleDeg(in_camera[i], in_camera[j]), AngleDeg(from_object[i], from_object[j])});
      }
    }
    // An object never seen whole needs one view more: its views are weaker evidence.
    const bool seen_enough = o.views_expected == 0 ||
                             o.views_seen >= kObjectMinSeenShare * static_cast<double>(o.views_expected);
    e.confirmed = e.observations >= kObjectMinObservations + (e.complete ? 0 : 1) &&
                  e.spread_deg >= kObjectMinSpreadDeg && seen_enough;
    e.plausible = PlausibleSize(e.class_name, e.dimensions, e.complete);
    e.exported = e.confirmed && e.plausible;
    out.push_back(e);
  }
  return out;
}

}  // namespace sgslam
