#include "sgslam/semantic/semantic_map.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <shared_mutex>
#include <unordered_map>

#include <spdlog/spdlog.h>

#include "sgslam/camera/camera.h"
#include "sgslam/common/se3.h"
#include "sgslam/common/stats.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/map/map.h"
#include "sgslam/semantic/dynamic_mask.h"
#include "sgslam/semantic/voxel_cell.h"

namespace sgslam {

namespace {

// A box carried from the box window (box_window.h) masks only pixels this close to
// its depth.
constexpr double kBoxWindowBand = 0.4;  // m
// px; pixel step when back-projecting a keyframe's depth into its cloud: about 1 cm
// at 2 m, under the 2 cm cloud voxel, and a ninth of the pixels, so that a keyframe
// costs milliseconds on one core.
constexpr int kCloudStride = 3;
// m; depth margin of the see-through test (filters.see_through) and of "at the
// same place" in the seen-moving test, plus kConsistencyToleranceQuadratic * z^2.
constexpr double kConsistencyTolerance = 0.05;
// The see-through test's margin grows with depth^2 (Kinect noise).
constexpr double kConsistencyToleranceQuadratic = 0.01;  // 1/m
// Keyframes that must see through a point to drop it (filters.see_through): one is
// enough (with 2, 1.18 % of the cloud was on movers on dyn_dev; with 1, 0.91 %).
constexpr int kConsistencyMinVotes = 1;
// Detections below this score give no object: weak detections are often the wrong
// class, and an object needs consistent views anyway.
constexpr double kObjectMinScore = 0.3;
// Keyframe depth is kept min-pooled by this factor for the export's multi-view tests.
constexpr int kDepthPool = 4;  // px
// Free-space rays are cast from every this-many-th pixel (hits: every cloud point).
constexpr int kOctoMapRayStride = 16;  // px
// A box this close to the image edge is a cut-off view of its object.
constexpr int kObjectBorder = 3;  // px

// Min over factor x factor blocks of the valid depths (m), 0 where a block has none:
// the nearest surface, so a see-through test never fires at a depth edge. With a
// mask, only the pixels it marks count.
cv::Mat MinPooledDepth(const cv::Mat& depth_raw, double depth_factor, int factor, const cv::Mat& mask = cv::Mat()) {
  cv::Mat out = cv::Mat::zeros(depth_raw.rows / factor, depth_raw.cols / factor, CV_32F);
  for (int y = 0; y < out.rows; ++y) {
    for (int x = 0; x < out.cols; ++x) {
      std::uint16_t best = 0;
      for (int dy = 0; dy < factor; ++dy) {
        const std::uint16_t* row = depth_raw.ptr<std::uint16_t>(y * factor + dy) + x * factor;
        const std::uint8_t* in = mask.empty() ? nullptr : mask.ptr<std::uint8_t>(y * factor + dy) + x * factor;
        for (int dx = 0; dx < factor; ++dx) {
          if (in != nullptr && in[dx] == 0) continue;
          if (row[dx] != 0 && (best == 0 || row[dx] < best)) best = row[dx];
        }
      }
      out.at<float>(y, x) = static_cast<float>(best / depth_factor);
    }
  }
  return out;
}

// The pixel of a pooled image (MinPooledDepth, of size `pooled`) that the
// camera-frame point q projects to; none outside the image.
std::optional<cv::Point> PooledPixel(cv::Size pooled, const Camera& camera, const Eigen::Vector3d& q, int factor) {
  const Eigen::Vector2d uv = camera.Distort(camera.Project(q));
  // Compared as doubles: a NaN or a huge coordinate must not reach the int cast.
  const double x = uv.x() / factor, y = uv.y() / factor;
  if (!(x >= 0 && y >= 0 && x < pooled.width && y < pooled.height)) return std::nullopt;
  return cv::Point(static_cast<int>(x), static_cast<int>(y));
}

}  // namespace

SemanticMap::SemanticMap(const SemanticConfig& config, std::shared_ptr<const Camera> camera, ClassTable classes,
                         const Map& map, std::unique_ptr<Detector> keyframe_detector,
                         const SemanticMapOptions& options)
    : config_(config),
      options_(options),
      map_(map),
      camera_(std::move(camera)),
      rays_(*camera_),
      classes_(std::move(classes)),
      keyframe_detector_(std::move(keyframe_detector)),
      has_keyframe_detector_(keyframe_detector_ != nullptr),
      octomap_(config),
      objects_(config, [cam = camera_](const Eigen::Vector3d& p_c) { return cam->Distort(cam->Project(p_c)); },
               cv::Size(camera_->width(), camera_->height())) {}

SemanticMap::StageMs SemanticMap::Add(const SemanticInput& input, const std::vector<CarriedBox>& carried) {
  SE3 T_w_c;
  {
    std::shared_lock lock(map_.mutex());
    T_w_c = input.keyframe->PlacedT_c_w().Inverse();
  }
  StageMs ms;
  Stopwatch stage;
  const KeyFrameBoxes boxes = Detect(input, T_w_c);
  const std::vector<Detection>& movers = boxes.movers;
  ms.detect = stage.ElapsedMs();
  ms.model_ran = boxes.model_ran;
  stage.Restart();
  // surface: where the movers themselves were, for the seen-moving filter (a whole
  // box would mark the background behind a person as seen moving).
  cv::Mat surface;
  cv::Mat mask = DynamicMask(input, movers, carried, config_.filters.seen_moving ? &surface : nullptr);
  // The objects leave the movers out (their own pixels where known: the mask also
  // holds the static surfaces around a rejected keypoint), not the image border.
  const cv::Mat movers_mask = !surface.empty() ? surface : config_.filters.image_border ? mask.clone() : mask;
  if (config_.filters.image_border) MaskImageBorder(mask);
  ms.mask = stage.ElapsedMs();
  stage.Restart();
  KeyFrameCloud cloud = MakeCloud(input, mask, surface);
  ms.cloud = stage.ElapsedMs();
  stage.Restart();
  std::vector<ColoredPoint> ray_points = BackProject(input.bgr, input.depth, camera_->config().depth_factor, mask,
                                                     rays_, kOctoMapRayStride, config_);
  octomap_.Insert(cloud.points_c, ray_points, T_w_c);
  ms.octomap = stage.ElapsedMs();
  clouds_.push_back(std::move(cloud));
  ray_points_.push_back(std::move(ray_points));
  stage.Restart();
  // A keyframe the keyframe model skipped (NewView) gives the objects no evidence,
  // seen or missing: their views are counted on the model's keyframes alone.
  if (boxes.model_ran || !keyframe_detector_) ObserveObjects(input, boxes.objects, T_w_c, movers_mask);
  ms.objects = stage.ElapsedMs();
  return ms;
}

void SemanticMap::Restore(SemanticState state) {
  clouds_.clear();
  ray_points_.clear();
  for (SemanticState::Cloud& c : state.clouds) {
    clouds_.push_back({c.keyframe, std::move(c.points_c), c.depth_pooled, c.moving_pooled});
    ray_points_.push_back(std::move(c.rays_c));
  }
  objects_.Restore(std::move(state.objects), state.next_object_id);
}

void SemanticMap::WriteOctoMap(const std::filesystem::path& path) { octomap_.Write(path); }

SemanticMap::Snapshot SemanticMap::Latest() const {
  Snapshot s;
  if (clouds_.empty()) return s;
  s.keyframe = clouds_.back().keyframe;
  s.cloud = std::make_shared<const std::vector<ColoredPoint>>(clouds_.back().points_c);
  // The estimate (which carves every object with every view) outside the map's
  // lock: local mapping must not wait for this low-priority thread.
  const std::unordered_map<const KeyFrame*, SE3> T_w_c = KeyFramePoses();
  s.objects = objects_.Estimate([&](const KeyFrame& kf) { return T_w_c.at(&kf); });
  s.cells = std::make_shared<const std::vector<Eigen::Vector4f>>(octomap_.OccupiedCells());
  return s;
}

std::size_t SemanticMap::ExportCloud(std::vector<Eigen::Vector3d>& points, std::vector<Rgb>& colours) {
  FilterAndRebuild();
  std::vector<ColoredPoint> world;
  for (const KeyFrameCloud& k : clouds_) {
    const SE3 T_w_c = k.keyframe->PlacedT_c_w().Inverse();
    for (const ColoredPoint& p : k.points_c) world.push_back({(T_w_c * p.p.cast<double>()).cast<float>(), p.rgb});
  }
  const std::vector<ColoredPoint> merged = VoxelDownsample(world, config_.cloud_voxel);
  points.clear();
  colours.clear();
  std::size_t freed = 0;
  for (const ColoredPoint& p : merged) {
    const Eigen::Vector3d x = p.p.cast<double>();
    if (!Exported(x)) {
      ++freed;
      continue;
    }
    points.push_back(x);
    colours.push_back(p.rgb);
  }
  return freed;
}

SemanticState SemanticMap::State() const {
  SemanticState state;
  state.clouds.reserve(clouds_.size());
  for (std::size_t i = 0; i < clouds_.size(); ++i) {
    const KeyFrameCloud& k = clouds_[i];
    state.clouds.push_back({k.keyframe, k.points_c, ray_points_[i], k.depth_pooled, k.moving_pooled});
  }
  state.objects = objects_.objects();
  state.next_object_id = objects_.next_id();
  return state;
}

std::unordered_map<const KeyFrame*, SE3> SemanticMap::KeyFramePoses() const {
  std::unordered_map<const KeyFrame*, SE3> T_w_c;
  std::shared_lock lock(map_.mutex());
  for (const KeyFrameCloud& k : clouds_) T_w_c.emplace(k.keyframe.get(), k.keyframe->PlacedT_c_w().Inverse());
  return T_w_c;
}

void SemanticMap::RebuildOctoMap() {
  std::vector<SE3> T_w_c;
  {
    std::shared_lock lock(map_.mutex());
    for (const KeyFrameCloud& c : clouds_) T_w_c.push_back(c.keyframe->PlacedT_c_w().Inverse());
  }
  octomap_.Clear();
  for (std::size_t i = 0; i < clouds_.size(); ++i) octomap_.Insert(clouds_[i].points_c, ray_points_[i], T_w_c[i]);
}

bool SemanticMap::NewView(const SE3& T_w_c) const {
  if (!model_T_w_c_) return true;
  const double scale = std::ldexp(1.0, std::clamp(model_level_.load(), 0, 16));
  const SE3 d = model_T_w_c_->Inverse() * T_w_c;
  const double angle_deg = so3::Log(d.quaternion()).norm() * 180.0 / M_PI;
  return angle_deg >= options_.model_view_deg * scale || d.translation().norm() >= options_.model_view_metres * scale;
}

SemanticMap::KeyFrameBoxes SemanticMap::Detect(const SemanticInput& input, const SE3& T_w_c) {
  // The keyframe's own boxes, plus what the larger keyframe model finds on a new
  // view: its movers join the mask, its other boxes give the objects (it names
  // them better). The mask needs it little (tracking's boxes and the motion
  // segments hold the movers): docs/experiments.md, "The keyframe model on fewer
  // keyframes".
  KeyFrameBoxes boxes;
  boxes.movers = input.keyframe->features->detections;
  if (keyframe_detector_ && NewView(T_w_c)) {
    try {
      boxes.objects = keyframe_detector_->Detect(input.bgr, input.keyframe->t);
      for (const Detection& d : boxes.objects) {
        if (classes_.is_dynamic(d.class_name)) boxes.movers.push_back(d);
      }
      boxes.model_ran = true;
      model_T_w_c_ = T_w_c;
      return boxes;
    } catch (const std::exception& e) {
      // The map goes on with tracking's boxes; the thread must not die with it.
      spdlog::warn("semantic map: the keyframe detector failed ({}); going on without it", e.what());
      keyframe_detector_.reset();
    }
  }
  if (!keyframe_detector_) boxes.objects = input.keyframe->features->detections;
  return boxes;
}

cv::Mat SemanticMap::DynamicMask(const SemanticInput& input, const std::vector<Detection>& movers,
                                    const std::vector<CarriedBox>& carried, cv::Mat* surface) const {
  const SemanticConfig& c = config_;
  const Features& f = *input.keyframe->features;
  const double depth_factor = camera_->config().depth_factor;
  DynamicMaskOptions options;  // the constants of dynamic_mask.h
  options.motion_segments = c.filters.motion_segments;
  cv::Mat mask =
      DynamicPixelMask(input.depth, depth_factor, movers, classes_, f.keys, f.dynamic, options, f.unjudged, surface);
  MaskCarriedBoxes(carried, input.depth, depth_factor, kBoxWindowBand, mask);
  if (surface) MaskCarriedBoxes(carried, input.depth, depth_factor, kSeenMovingBand, *surface);
  return mask;
}

void SemanticMap::MaskImageBorder(cv::Mat& mask) {
  // No keypoint (ORB's edge margin) and so no motion evidence reaches the border,
  // and the detector misses the people it cuts: it stays out of the map.
  const int b = std::min({kImageBorder, mask.cols / 2, mask.rows / 2});
  mask.rowRange(0, b).setTo(255), mask.rowRange(mask.rows - b, mask.rows).setTo(255);
  mask.colRange(0, b).setTo(255), mask.colRange(mask.cols - b, mask.cols).setTo(255);
}

SemanticMap::KeyFrameCloud SemanticMap::MakeCloud(const SemanticInput& input, const cv::Mat& mask,
                                                        const cv::Mat& surface) const {
  const SemanticConfig& c = config_;
  const double depth_factor = camera_->config().depth_factor;
  const bool seen_moving = c.filters.seen_moving;
  KeyFrameCloud cloud;
  cloud.keyframe = input.keyframe;
  cloud.points_c =
      VoxelDownsample(BackProject(input.bgr, input.depth, depth_factor, mask, rays_, kCloudStride, c), c.cloud_voxel);
  if (c.filters.see_through || seen_moving) cloud.depth_pooled = MinPooledDepth(input.depth, depth_factor, kDepthPool);
  if (seen_moving) cloud.moving_pooled = MinPooledDepth(input.depth, depth_factor, kDepthPool, surface);
  return cloud;
}

void SemanticMap::ObserveObjects(const SemanticInput& input, const std::vector<Detection>& detections,
                                 const SE3& T_w_c, const cv::Mat& movers_mask) {
  const SemanticConfig& c = config_;
  const double depth_factor = camera_->config().depth_factor;
  // The objects' views at the keyframes' current poses (bundle adjustment, loop
  // corrections).
  const std::unordered_map<const KeyFrame*, SE3> T = KeyFramePoses();
  objects_.Refresh([&](const KeyFrame& kf) { return T.at(&kf); });
  // Sec. III-E: every detection except those of dynamic objects (people, dogs).
  const auto gives_object = [&](const Detection& d) {
    return !classes_.is_dynamic(d.class_name) && d.score >= kObjectMinScore;
  };
  // Every box of the frame, people's too, may hide part of another (computed only
  // when some detection gives an object: most keyframes of a dynamic scene have none).
  const std::vector<double> object_depths = std::any_of(detections.begin(), detections.end(), gives_object)
                                                ? ObjectDepths(detections, input.depth, depth_factor, c)
                                                : std::vector<double>();
  std::vector<int> joined;
  for (std::size_t i = 0; i < detections.size(); ++i) {
    const Detection& d = detections[i];
    if (!gives_object(d)) continue;
    std::vector<OtherBox> others;
    for (std::size_t j = 0; j < detections.size(); ++j) {
      if (j != i) others.push_back({detections[j].box, object_depths[j]});
    }
    auto obs = ObserveObject(d, input.depth, depth_factor, rays_, c, others, movers_mask);
    if (!obs) continue;
    obs->keyframe = input.keyframe;
    const int b = kObjectBorder;
    // A box cut by the image border is a partial view; it may still start an
    // object (one never seen whole is still in the room).
    obs->cut = d.box.x < b || d.box.y < b || d.box.x + d.box.width > input.depth.cols - b ||
               d.box.y + d.box.height > input.depth.rows - b;
    joined.push_back(objects_.Add(std::move(*obs), T_w_c));
  }
  objects_removed_ += static_cast<std::size_t>(objects_.CountViews(joined, T_w_c, input.depth, depth_factor, movers_mask));
}

void SemanticMap::FilterAndRebuild() {
  if (filtered_) return;
  filtered_ = true;
  const SemanticFilters& f = config_.filters;
  if (!f.see_through && !f.view_support && !f.seen_moving) {
    octomap_.Finalize();
    return;
  }
  std::vector<SE3> T_c_w(clouds_.size()), T_w_c(clouds_.size());
  for (std::size_t k = 0; k < clouds_.size(); ++k) {
    T_c_w[k] = clouds_[k].keyframe->PlacedT_c_w();
    T_w_c[k] = T_c_w[k].Inverse();
  }
  if (f.see_through || f.seen_moving) DropPointsOtherViewsContradict(T_c_w, T_w_c);
  if (f.view_support) DropPointsSeenOnce(T_w_c);
  // The live OctoMap saw the moving points too, with the poses of the time: build
  // it again from the points that passed and the final poses.
  octomap_.Clear();
  for (std::size_t i = 0; i < clouds_.size(); ++i) octomap_.Insert(clouds_[i].points_c, ray_points_[i], T_w_c[i]);
  octomap_.Finalize();
}

void SemanticMap::DropPointsOtherViewsContradict(const std::vector<SE3>& T_c_w, const std::vector<SE3>& T_w_c) {
  const SemanticConfig& c = config_;
  const bool see_through = c.filters.see_through;
  const bool seen_moving = c.filters.seen_moving;
  for (std::size_t i = 0; i < clouds_.size(); ++i) {
    std::vector<ColoredPoint> kept;
    kept.reserve(clouds_[i].points_c.size());
    for (const ColoredPoint& p : clouds_[i].points_c) {
      const Eigen::Vector3d x = T_w_c[i] * p.p.cast<double>();
      int through = 0, moving = 0, still = 1;  // keyframe i saw it, unmasked
      for (std::size_t j = 0; j < clouds_.size(); ++j) {
        if (j == i || clouds_[j].depth_pooled.empty()) continue;
        const Eigen::Vector3d q = T_c_w[j] * x;
        if (q.z() < c.depth_min || q.z() > c.depth_max) continue;
        const std::optional<cv::Point> px = PooledPixel(clouds_[j].depth_pooled.size(), *camera_, q, kDepthPool);
        if (!px) continue;
        const float z = clouds_[j].depth_pooled.at<float>(*px);
        const double tolerance = kConsistencyTolerance + kConsistencyToleranceQuadratic * q.z() * q.z();
        if (see_through && z > 0 && z > q.z() + tolerance) {
          if (++through >= kConsistencyMinVotes) break;  // keyframe j sees what lies behind the point
        }
        // A cloud made without the seen-moving filter (a loaded map) has no movers' depth.
        if (!seen_moving || clouds_[j].moving_pooled.size() != clouds_[j].depth_pooled.size()) continue;
        const float zm = clouds_[j].moving_pooled.at<float>(*px);
        if (zm > 0 && std::abs(zm - q.z()) <= tolerance) {
          ++moving;  // keyframe j masked a mover right there
        } else if (z > 0 && std::abs(z - q.z()) <= tolerance) {
          ++still;  // keyframe j saw the surface there, unmasked
        }
      }
      if (see_through && through >= kConsistencyMinVotes) {
        ++inconsistent_;
      } else if (seen_moving && moving > 0 && moving >= options_.seen_moving_ratio * still) {
        ++seen_moving_;
      } else {
        kept.push_back(p);
      }
    }
    clouds_[i].points_c.swap(kept);
  }
}

void SemanticMap::DropPointsSeenOnce(const std::vector<SE3>& T_w_c) {
  // Which keyframes put a point into each OctoMap-sized voxel.
  const double inv = 1.0 / config_.octomap_resolution;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> views;
  std::size_t total = 0;
  for (const KeyFrameCloud& k : clouds_) total += k.points_c.size();
  views.reserve(total);
  std::vector<std::vector<VoxelCell>> cells(clouds_.size());
  for (std::size_t i = 0; i < clouds_.size(); ++i) {
    cells[i].reserve(clouds_[i].points_c.size());
    for (const ColoredPoint& p : clouds_[i].points_c) {
      cells[i].push_back(VoxelCell::Of(T_w_c[i] * p.p.cast<double>(), inv));
      auto& v = views[cells[i].back().Key()];
      if (v.empty() || v.back() != i) v.push_back(static_cast<std::uint32_t>(i));  // i grows: no duplicates
    }
  }
  // A point stays when enough keyframes put points into its voxel or the 26 around
  // it (pose and depth noise spread one surface over neighbouring voxels).
  const auto need = static_cast<std::size_t>(kMinViewSupport);
  std::vector<std::uint32_t> seen;
  for (std::size_t i = 0; i < clouds_.size(); ++i) {
    std::vector<ColoredPoint> kept;
    kept.reserve(clouds_[i].points_c.size());
    for (std::size_t k = 0; k < clouds_[i].points_c.size(); ++k) {
      const VoxelCell& cell = cells[i][k];
      seen.clear();
      const auto count = [&](int dx, int dy, int dz) {
        const auto it = views.find(cell.Shifted(dx, dy, dz).Key());
        if (it == views.end()) return;
        for (std::uint32_t j : it->second) {
          if (std::find(seen.begin(), seen.end(), j) == seen.end()) seen.push_back(j);
          if (seen.size() >= need) return;
        }
      };
      count(0, 0, 0);  // on a static surface the point's own voxel is usually enough
      for (int n = 0; n < 27 && seen.size() < need; ++n) {
        if (n != 13) count(n / 9 - 1, (n / 3) % 3 - 1, n % 3 - 1);
      }
      if (seen.size() >= need) {
        kept.push_back(clouds_[i].points_c[k]);
      } else {
        ++unsupported_;
      }
    }
    clouds_[i].points_c.swap(kept);
  }
}

std::vector<SemanticMap::KeyFramePoints> SemanticMap::KeyFrameClouds() const {
  std::vector<KeyFramePoints> out;
  out.reserve(clouds_.size());
  for (const KeyFrameCloud& k : clouds_) out.push_back({k.keyframe, &k.points_c});
  return out;
}

bool SemanticMap::Exported(const Eigen::Vector3d& p_w) const {
  // A voxel that later views saw through held something that moved away.
  return !(config_.filters.free_space && octomap_.IsFree(p_w));
}

std::vector<ObjectEstimate> SemanticMap::ExportObjects(const SE3& T_out_w) const {
  return objects_.Estimate([](const KeyFrame& kf) { return kf.PlacedT_c_w().Inverse(); }, T_out_w);
}

}  // namespace sgslam
