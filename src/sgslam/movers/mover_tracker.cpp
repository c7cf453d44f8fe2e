#include "sgslam/movers/mover_tracker.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "sgslam/common/stats.h"

namespace sgslam::movers {

namespace {

// Observations (step 1).
constexpr int kSampleTarget = 300;  // depth samples per box, on a regular grid
constexpr int kMinSamples = 12;     // fewer on the mover: no observation
constexpr std::size_t kMaxPoints = 48;  // points kept per observation and track (footprint, outputs)
// m, half-width of the depth band around the mover's seed depth that is the mover:
// a person is 0.2-0.5 m deep, the wall behind it usually more than that away.
constexpr double kBand = 0.35;
constexpr double kForegroundShare = 0.25;  // share of a box's depth samples the mover's surface holds at least
constexpr double kMinMovingShare = 0.2;  // share of a box's keypoints on the mover that must move for evidence
constexpr int kMinMovingKeypoints = 2;
constexpr float kClusterRadius = 30.f;  // px, single linkage of moving keypoints
constexpr double kClusterDepth = 0.3;   // m, and at most this far apart in depth
constexpr std::size_t kMinClusterSize = 5;
constexpr float kBoxMargin = 0.15f;  // share of a box's size around it whose keypoints seed no cluster
constexpr float kClusterMargin = 8.f;  // px around the cluster's keypoints for its depth samples
constexpr double kMinFrontDepth = 0.1;  // m, nearer a point is not projected
// Association and motion (steps 2-3).
constexpr double kGate = 0.6;             // m, base gate around a track's predicted centroid
constexpr double kMaxGateGrowth = 0.6;    // m, plus speed * time since the last observation, at most this
constexpr std::size_t kVelocityWindow = 10;  // observations in the velocity fit (a third of a second at 30 Hz)
constexpr double kMinVelocitySpan = 0.1;  // s, shortest history the velocity is fitted on
constexpr double kMaxSpeed = 3.0;         // m/s, faster is an association error
constexpr double kReacquireSpeed = 1.5;  // m/s, a walker's pace: how far a lost track's mover may have gone
constexpr double kMaxReacquire = 2.0;    // m, at most
constexpr double kExtentGain = 0.3;       // share of a new observation's extent
constexpr double kMerge = 0.35;  // m, two tracks nearer than this are one mover
constexpr double kMinUnknownSpeed = 0.1;  // m/s, a class-less track must travel this fast to be confirmed
constexpr double kAbsorb = 0.5;  // m, an unmatched cluster this near a track is part of it, not a new mover
// States (step 4).
constexpr int kConfirmHits = 3;
constexpr int kConfirmEvidence = 2;
constexpr int kCoast = 5;              // frames a confirmed track stays confirmed unobserved
constexpr int kTentativeMisses = 3;    // frames an unconfirmed track lives unobserved
constexpr double kForget = 1.0;        // s without an observation: forgotten
// Footprints.
constexpr double kPredictFor = 0.5;  // s since the last observation a footprint is still predicted
constexpr float kFootprintMargin = 6.f;  // px around the projected points
constexpr int kMinFootprintPoints = 5;

// The smallest box holding the points, grown by margin on every side.
cv::Rect2f Bounds(const std::vector<cv::Point2f>& pts, float margin) {
  float x0 = pts[0].x, y0 = pts[0].y, x1 = x0, y1 = y0;
  for (const cv::Point2f& p : pts) x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  return {x0 - margin, y0 - margin, x1 - x0 + 2 * margin, y1 - y0 + 2 * margin};
}

cv::Rect2f Grow(const cv::Rect2f& r, float share) {
  return {r.x - share * r.width, r.y - share * r.height, r.width * (1 + 2 * share), r.height * (1 + 2 * share)};
}

cv::Rect2f Clip(const cv::Rect2f& r, cv::Size image) {
  return r & cv::Rect2f(0.f, 0.f, static_cast<float>(image.width), static_cast<float>(image.height));
}

// The depth of the nearest surface that holds kForegroundShare of the box's depth
// samples z: a mover is in front of what it hides.
double ForegroundDepth(std::vector<double> z) {
  std::sort(z.begin(), z.end());
  const auto need = static_cast<std::size_t>(kForegroundShare * static_cast<double>(z.size()));
  for (std::size_t i = 0, j = 0; i < z.size(); ++i) {  // windows of 2 * kBand, front to back
    while (j < z.size() && z[j] < z[i] + 2 * kBand) ++j;
    if (j - i >= need) return Median(std::vector<double>(z.begin() + static_cast<std::ptrdiff_t>(i), z.begin() + static_cast<std::ptrdiff_t>(j)));
  }
  return Median(std::move(z));
}

// The velocity: least-squares slope of the observed centroids over time.
Eigen::Vector3d FitVelocity(const std::deque<std::pair<Timestamp, Eigen::Vector3d>>& h) {
  if (h.size() < 3 || ToSeconds(h.back().first - h.front().first) < kMinVelocitySpan) return Eigen::Vector3d::Zero();
  double mean_t = 0;
  Eigen::Vector3d mean_p = Eigen::Vector3d::Zero();
  for (const auto& [t, p] : h) mean_t += ToSeconds(t - h.front().first), mean_p += p;
  mean_t /= static_cast<double>(h.size());
  mean_p /= static_cast<double>(h.size());
  double stt = 0;
  Eigen::Vector3d stp = Eigen::Vector3d::Zero();
  for (const auto& [t, p] : h) {
    const double dt = ToSeconds(t - h.front().first) - mean_t;
    stt += dt * dt;
    stp += dt * (p - mean_p);
  }
  Eigen::Vector3d v = stp / stt;
  if (v.norm() > kMaxSpeed) v *= kMaxSpeed / v.norm();
  return v;
}

// A class-less observation (a cluster: often a part of a mover) updates only a
// class-less track; a box updates a track of its class or names a class-less one.
bool Compatible(const std::string& track_class, const std::string& obs_class) {
  return track_class == kUnknownClass || track_class == obs_class;
}

bool SameMover(const std::string& a, const std::string& b) {
  return a == kUnknownClass || b == kUnknownClass || a == b;
}

}  // namespace

const char* StateName(TrackState state) {
  switch (state) {
    case TrackState::kTentative: return "tentative";
    case TrackState::kConfirmed: return "confirmed";
    case TrackState::kLost: return "lost";
  }
  return "?";
}

bool MoverTracker::SegmentBox(const cv::Mat& depth_raw, const cv::Rect2f& box_in, double seed_depth, const SE3& T_w_c,
                              Observation& out) const {
  const cv::Rect2f box = Clip(box_in, depth_raw.size());
  if (box.width < 2 || box.height < 2 || depth_raw.type() != CV_16U) return false;
  const float step = std::max(1.f, std::sqrt(box.area() / static_cast<float>(kSampleTarget)));
  std::vector<cv::Point2f> samples;
  std::vector<double> sample_depths;
  for (float v = box.y + 0.5f * step; v < box.y + box.height; v += step) {
    for (float u = box.x + 0.5f * step; u < box.x + box.width; u += step) {
      const double z = camera_->DepthMetres(depth_raw.at<std::uint16_t>(static_cast<int>(v), static_cast<int>(u)));
      if (z > 0) samples.emplace_back(u, v), sample_depths.push_back(z);
    }
  }
  if (static_cast<int>(samples.size()) < kMinSamples) return false;
  if (seed_depth <= 0) seed_depth = ForegroundDepth(sample_depths);
  std::vector<cv::Point2f> pixels;
  std::vector<double> depths;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (std::abs(sample_depths[i] - seed_depth) < kBand) pixels.push_back(samples[i]), depths.push_back(sample_depths[i]);
  }
  if (static_cast<int>(pixels.size()) < kMinSamples) return false;
  if (camera_->has_distortion()) camera_->Undistort(pixels);
  std::vector<Eigen::Vector3d> points(pixels.size());
  out.centroid.setZero();
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    points[i] = T_w_c * camera_->Unproject(pixels[i].x, pixels[i].y, depths[i]);
    out.centroid += points[i];
  }
  out.centroid /= static_cast<double>(points.size());
  for (int a = 0; a < 3; ++a) {
    std::vector<double> c(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) c[i] = points[i][a];
    out.extent[a] = Percentile(c, 0.9) - Percentile(c, 0.1);
  }
  const std::size_t stride = (points.size() + kMaxPoints - 1) / kMaxPoints;
  out.points.clear();
  for (std::size_t i = 0; i < points.size(); i += stride) out.points.push_back(points[i]);
  return true;
}

bool MoverTracker::BoxObservation(const FrameInput& in, int box, double seed_depth, Observation& o) const {
  const Detection& d = (*in.boxes)[static_cast<std::size_t>(box)];
  o.class_name = d.class_name;
  o.box = d.box;
  o.source = box;
  if (!SegmentBox(in.depth_raw, d.box, seed_depth, in.T_c_w.Inverse(), o)) return false;
  // Evidence: the keypoints on the mover (in its depth band) that moved on their own.
  const std::vector<float>& depth = *in.depth;
  const std::vector<std::uint8_t>& moving = *in.moving;
  const double z0 = (in.T_c_w * o.centroid).z();
  int on = 0, moved = 0;
  for (std::size_t i = 0; i < in.keys->size(); ++i) {
    if (!d.box.contains((*in.keys)[i].pt) || depth[i] <= 0 || std::abs(depth[i] - z0) > 2 * kBand) continue;
    ++on;
    moved += i < moving.size() && moving[i] != 0 ? 1 : 0;
  }
  o.moving = moved >= kMinMovingKeypoints && moved >= kMinMovingShare * on;
  return true;
}

std::vector<Observation> MoverTracker::Observe(const FrameInput& in) const {
  std::vector<Observation> obs;
  const std::vector<cv::KeyPoint>& keys = *in.keys;
  const std::vector<float>& depth = *in.depth;
  const std::vector<std::uint8_t>& moving = *in.moving;
  const SE3 T_w_c = in.T_c_w.Inverse();
  auto is_moving = [&](std::size_t i) { return i < moving.size() && moving[i] != 0 && depth[i] > 0; };

  // Fresh boxes of moving-object classes are observations. Every box of such a
  // class (followed between detector frames, carried, predicted) holds its mover's
  // moving keypoints and the uncovered background at its edges: no cluster there.
  std::vector<std::uint8_t> in_box(keys.size(), 0);
  for (std::size_t b = 0; in.boxes && b < in.boxes->size(); ++b) {
    const Detection& d = (*in.boxes)[b];
    if (!classes_.is_dynamic(d.class_name)) continue;
    const cv::Rect2f near = Grow(d.box, kBoxMargin);
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (near.contains(keys[i].pt)) in_box[i] = 1;
    }
    Observation o;
    if (in.fresh_boxes && d.carried == 0 && BoxObservation(in, static_cast<int>(b), 0.0, o)) obs.push_back(std::move(o));
  }

  // Clusters of moving keypoints outside those boxes (single linkage in the image and in depth).
  std::vector<std::size_t> seeds;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (is_moving(i) && !in_box[i]) seeds.push_back(i);
  }
  std::vector<std::size_t> parent(seeds.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (std::size_t a = 0; a < seeds.size(); ++a) {
    for (std::size_t b = a + 1; b < seeds.size(); ++b) {
      const cv::Point2f d = keys[seeds[a]].pt - keys[seeds[b]].pt;
      if (d.dot(d) < kClusterRadius * kClusterRadius && std::abs(depth[seeds[a]] - depth[seeds[b]]) < kClusterDepth) {
        parent[root(a)] = root(b);
      }
    }
  }
  std::vector<std::vector<std::size_t>> clusters(seeds.size());
  for (std::size_t a = 0; a < seeds.size(); ++a) clusters[root(a)].push_back(seeds[a]);
  for (const std::vector<std::size_t>& c : clusters) {
    if (c.size() < kMinClusterSize) continue;
    std::vector<cv::Point2f> pts;
    std::vector<double> z;
    for (const std::size_t i : c) pts.push_back(keys[i].pt), z.push_back(depth[i]);
    const cv::Rect2f box = Bounds(pts, kClusterMargin);
    Observation o;
    o.class_name = kUnknownClass;
    o.box = Clip(box, in.depth_raw.size());
    o.moving = true;
    if (SegmentBox(in.depth_raw, o.box, Median(z), T_w_c, o)) obs.push_back(std::move(o));
  }
  return obs;
}

void MoverTracker::Update(const FrameInput& in) {
  std::vector<Observation> obs = Observe(in);
  for (const Observation& o : obs) {
    ++stats_.observations;
    ++(o.class_name == kUnknownClass ? stats_.cluster_observations : stats_.box_observations);
  }
  // A box a track is predicted in is also cut at the track's depth: a mover partly
  // hidden by a nearer one has its box's foreground on the other.
  const std::size_t observed = obs.size();
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    const Eigen::Vector3d p = in.T_c_w * tracks_[k].PositionAt(in.t);
    if (p.z() < kMinFrontDepth) continue;
    const Eigen::Vector2d uv = camera_->has_distortion() ? camera_->Distort(camera_->Project(p)) : camera_->Project(p);
    for (std::size_t j = 0; j < observed; ++j) {
      if (obs[j].source < 0 || !Compatible(tracks_[k].class_name, obs[j].class_name) ||
          !obs[j].box.contains(cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()))) ||
          std::abs((in.T_c_w * obs[j].centroid).z() - p.z()) < kBand) {
        continue;
      }
      Observation o;
      if (!BoxObservation(in, obs[j].source, p.z(), o)) continue;
      o.guided = static_cast<int>(k);
      obs.push_back(std::move(o));
    }
  }
  // Step 2: nearest compatible pairs first; a box observes one mover.
  struct Pair {
    double d;
    std::size_t track, obs;
  };
  std::vector<Pair> pairs;
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    const Track& tr = tracks_[k];
    const double dt = ToSeconds(in.t - tr.updated);
    const double gate = kGate + std::min(kMaxGateGrowth, tr.velocity.norm() * std::min(dt, Track::kHorizon));
    const Eigen::Vector3d predicted = tr.PositionAt(in.t);
    for (std::size_t j = 0; j < obs.size(); ++j) {
      if (!Compatible(tr.class_name, obs[j].class_name) || (obs[j].guided >= 0 && obs[j].guided != static_cast<int>(k))) {
        continue;
      }
      const double d = (obs[j].centroid - predicted).norm();
      if (d < gate) pairs.push_back({d, k, j});
    }
  }
  std::vector<bool> track_taken(tracks_.size(), false), obs_taken(obs.size(), false);
  for (Track& tr : tracks_) tr.observed = false;
  const auto assign = [&](std::vector<Pair>& candidates) {
    std::sort(candidates.begin(), candidates.end(), [](const Pair& a, const Pair& b) { return a.d < b.d; });
    for (const Pair& p : candidates) {
      if (track_taken[p.track] || obs_taken[p.obs]) continue;
      track_taken[p.track] = obs_taken[p.obs] = true;
      // Nothing else of that box, nor another view of that mover (the foreground of a
      // box it hides part of), observes another track.
      for (std::size_t j = 0; j < obs.size(); ++j) {
        const bool same_box = obs[p.obs].source >= 0 && obs[j].source == obs[p.obs].source;
        obs_taken[j] = obs_taken[j] || same_box || (obs[j].centroid - obs[p.obs].centroid).norm() < kMerge;
      }
      // Step 3.
      Track& tr = tracks_[p.track];
      const Observation& o = obs[p.obs];
      tr.position = o.centroid;  // smoothing it lagged and cost dyn_dev coverage (0.84 -> 0.96 without)
      tr.history.emplace_back(in.t, o.centroid);
      while (tr.history.size() > kVelocityWindow) tr.history.pop_front();
      tr.velocity = FitVelocity(tr.history);
      tr.extent += kExtentGain * (o.extent - tr.extent);
      tr.points.clear();
      for (const Eigen::Vector3d& q : o.points) tr.points.push_back(q - o.centroid);
      if (tr.class_name == kUnknownClass) tr.class_name = o.class_name;  // a box names it
      tr.updated = in.t;
      ++tr.hits;
      tr.moving_hits += o.moving ? 1 : 0;
      tr.misses = 0;
      tr.observed = true;
      const bool was = tr.state != TrackState::kTentative;
      // A class-less track is only geometry's word: it must also be seen to travel.
      const bool travels = tr.class_name != kUnknownClass || tr.velocity.norm() >= kMinUnknownSpeed;
      if (was || (tr.hits >= kConfirmHits && tr.moving_hits >= kConfirmEvidence && travels)) {
        tr.state = TrackState::kConfirmed;
        if (!was) ++stats_.confirmed;
      }
    }
  };
  assign(pairs);
  // A lost track's mover back in view (after an occlusion, a stretch of missed
  // detections): within the distance a walker covers meanwhile, from what is left.
  // (Clusters too, so that the geometry would follow a person the detector misses:
  // dyn_dev's worst mover went from 11 to 32 id switches.)
  pairs.clear();
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    const Track& tr = tracks_[k];
    if (tr.state != TrackState::kLost || track_taken[k]) continue;
    const double gate = std::min(kMaxReacquire, kGate + kReacquireSpeed * ToSeconds(in.t - tr.updated));
    for (std::size_t j = 0; j < observed; ++j) {
      if (obs_taken[j] || !Compatible(tr.class_name, obs[j].class_name)) continue;
      const double d = (obs[j].centroid - tr.PositionAt(in.t)).norm();
      if (d < gate) pairs.push_back({d, k, j});
    }
  }
  assign(pairs);
  // New tracks from what is left, unless it is a piece of a mover already tracked.
  for (std::size_t j = 0; j < observed; ++j) {
    if (obs_taken[j]) continue;
    const Observation& o = obs[j];
    const bool absorbed = o.class_name == kUnknownClass && std::any_of(tracks_.begin(), tracks_.end(), [&](const Track& tr) {
      return (tr.observed || tr.state != TrackState::kTentative) && (tr.PositionAt(in.t) - o.centroid).norm() < kAbsorb;
    });
    if (absorbed) continue;
    Track tr;
    tr.id = next_id_++;
    tr.class_name = o.class_name;
    tr.position = o.centroid;
    tr.extent = o.extent;
    for (const Eigen::Vector3d& q : o.points) tr.points.push_back(q - o.centroid);
    tr.born = tr.updated = in.t;
    tr.hits = 1;
    tr.moving_hits = o.moving ? 1 : 0;
    tr.observed = true;
    tr.history.emplace_back(in.t, o.centroid);
    tracks_.push_back(std::move(tr));
    ++stats_.tracks;
  }
  MergeDuplicates();
  Age(in.t);
}

void MoverTracker::MergeDuplicates() {
  // Two tracks on one mover (a box and a cluster of its keypoints, a box found
  // twice): the one confirmed, else observed more often, stays.
  std::vector<bool> gone(tracks_.size(), false);
  for (std::size_t a = 0; a < tracks_.size(); ++a) {
    for (std::size_t b = a + 1; b < tracks_.size() && !gone[a]; ++b) {
      Track& ta = tracks_[a];
      Track& tb = tracks_[b];
      // Two confirmed tracks near each other are two movers passing.
      const bool both = ta.state != TrackState::kTentative && tb.state != TrackState::kTentative;
      if (gone[b] || both || !SameMover(ta.class_name, tb.class_name) || (ta.position - tb.position).norm() >= kMerge) {
        continue;
      }
      const auto rank = [](const Track& t) { return std::make_pair(t.state != TrackState::kTentative, t.hits); };
      const bool keep_a = rank(ta) >= rank(tb);
      Track& keep = keep_a ? ta : tb;
      const Track& drop = keep_a ? tb : ta;
      if (keep.class_name == kUnknownClass) keep.class_name = drop.class_name;
      gone[keep_a ? b : a] = true;
    }
  }
  std::size_t k = 0;
  std::erase_if(tracks_, [&](const Track&) { return gone[k++]; });
}

void MoverTracker::Skip(Timestamp t) {
  for (Track& tr : tracks_) tr.observed = false;
  Age(t);
}

void MoverTracker::Age(Timestamp t) {
  for (Track& tr : tracks_) {
    if (tr.observed) continue;
    ++tr.misses;
    if (tr.state == TrackState::kConfirmed && tr.misses > kCoast) tr.state = TrackState::kLost;
  }
  std::erase_if(tracks_, [t](const Track& tr) {
    return (tr.state == TrackState::kTentative && tr.misses >= kTentativeMisses) || ToSeconds(t - tr.updated) > kForget;
  });
}

std::vector<Detection> MoverTracker::Footprints(const SE3& T_c_w, Timestamp t) const {
  std::vector<Detection> out;
  const cv::Size image(camera_->width(), camera_->height());
  for (const Track& tr : tracks_) {
    if (tr.state == TrackState::kTentative || ToSeconds(t - tr.updated) > kPredictFor) continue;
    const Eigen::Vector3d centre = tr.PositionAt(t);
    std::vector<cv::Point2f> px;
    for (const Eigen::Vector3d& q : tr.points) {
      const Eigen::Vector3d p = T_c_w * (centre + q);
      if (p.z() < kMinFrontDepth) continue;
      const Eigen::Vector2d uv = camera_->has_distortion() ? camera_->Distort(camera_->Project(p)) : camera_->Project(p);
      px.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    }
    if (static_cast<int>(px.size()) < kMinFootprintPoints) continue;
    const cv::Rect2f box = Clip(Bounds(px, kFootprintMargin), image);
    if (box.width < 2 * kFootprintMargin || box.height < 2 * kFootprintMargin) continue;
    Detection d;
    d.class_name = tr.class_name;
    d.score = 1.f;
    d.box = box;
    d.carried = 1;
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace sgslam::movers
