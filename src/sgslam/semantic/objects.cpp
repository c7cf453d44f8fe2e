#include "sgslam/semantic/objects.h"

#include <algorithm>
#include <cmath>

#include "sgslam/common/stats.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/semantic/background_planes.h"

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
                                               const ObserveObjectOptions& options) {
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
  for (std::size_t i = 0; i < depths.size(); ++i) {
    if (std::abs(depths[i] - median) > band) continue;
    // Where another box covers the pixel, it goes to the object whose depth is nearer.
    const bool theirs = std::any_of(overlapping.begin(), overlapping.end(), [&](const OtherBox& o) {
      return InBox(pixels[i], o.box) && std::abs(depths[i] - o.depth) < std::abs(depths[i] - median);
    });
    if (theirs) continue;
    const cv::Vec2f& r = rays.at(pixels[i].x, pixels[i].y);
    const auto z = static_cast<float>(depths[i]);
    points.emplace_back(r[0] * z, r[1] * z, z);
  }
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

ObjectDatabase::Box ObjectDatabase::BoxOf(const std::vector<Eigen::Vector3d>& points) const {
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

int ObjectDatabase::Add(ObjectObservation observation, const SE3& T_w_c) {
  std::vector<Eigen::Vector3d> world;
  world.reserve(observation.points_c.size());
  for (const auto& p : observation.points_c) world.push_back(T_w_c * p.cast<double>());
  const Box box = BoxOf(world);
  const Eigen::Vector3d centre = (box.min + box.max) / 2;
  Object* best = nullptr;
  double best_score = 0;
  for (Object& o : objects_) {
    if (o.class_id != observation.class_id || o.class_name != observation.class_name) continue;
    const Eigen::Vector3d lo = box.min.cwiseMax(o.box.min), hi = box.max.cwiseMin(o.box.max);
    const double inter = Volume(lo, hi);
    const double iou = inter / std::max(Volume(box.min, box.max) + Volume(o.box.min, o.box.max) - inter, 1e-12);
    const Eigen::Vector3d o_centre = (o.box.min + o.box.max) / 2;
    // A partial first view gives a small box: a centre inside the other box counts too.
    const Eigen::Vector3d m = Eigen::Vector3d::Constant(kMergeMargin);
    const bool nested = Inside(centre, o.box.min - m, o.box.max + m) || Inside(o_centre, box.min - m, box.max + m);
    const double score = iou + (nested ? 1.0 : 0.0);
    if ((iou > kObjectMergeIou || nested) && score > best_score) {
      best = &o;
      best_score = score;
    }
  }
  std::size_t index = 0;
  if (best == nullptr) {
    objects_.push_back({next_id_++, observation.class_id, observation.class_name, {}, box});
    index = objects_.size() - 1;
  } else {
    index = static_cast<std::size_t>(best - objects_.data());
  }
  Object& o = objects_[index];
  observation.T_w_c_added = T_w_c;
  o.observations.push_back(std::move(observation));
  if (o.observations.size() > 1) {
    std::vector<SE3> poses;
    for (const ObjectObservation& obs : o.observations) poses.push_back(obs.T_w_c_added);
    o.box = BoxOf(CarvedPoints(o, poses));
  }
  return o.id;
}

bool ObjectDatabase::Complete(const Object& o) {
  return std::any_of(o.observations.begin(), o.observations.end(), [](const ObjectObservation& ob) { return !ob.cut; });
}

std::vector<Eigen::Vector3d> ObjectDatabase::CarvedPoints(const Object& o, const std::vector<SE3>& T_w_c) const {
  const std::size_t n = o.observations.size();
  std::vector<SE3> T_c_w(n);
  for (std::size_t j = 0; j < n; ++j) T_c_w[j] = T_w_c[j].Inverse();
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
      for (std::size_t j = 0; j < n && project_; ++j) {
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
    for (const ObjectObservation& obs : o.observations) {
      T_w_c.push_back(obs.keyframe ? pose_of(*obs.keyframe) : obs.T_w_c_added);
      score += obs.score;
    }
    std::vector<Eigen::Vector3d> points = CarvedPoints(o, T_w_c);
    for (auto& p : points) p = T_out_w * p;
    const Box b = BoxOf(points);
    ObjectEstimate e;
    e.id = o.id;
    e.class_id = o.class_id;
    e.class_name = o.class_name;
    e.observations = static_cast<int>(o.observations.size());
    const double mean_score = o.observations.empty() ? 0.0 : score / static_cast<double>(o.observations.size());
    e.confidence = mean_score * (1.0 - std::exp(-e.observations / 2.0));
    e.centroid = (b.min + b.max) / 2;
    e.size = b.max - b.min;
    e.complete = Complete(o);
    // An object never seen whole needs one view more: its views are weaker evidence.
    e.exported = e.observations >= kObjectMinObservations + (e.complete ? 0 : 1);
    out.push_back(e);
  }
  return out;
}

}  // namespace sgslam
