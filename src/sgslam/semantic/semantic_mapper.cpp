#include "sgslam/semantic/semantic_mapper.h"

#include <shared_mutex>

#include "sgslam/camera/camera.h"
#include "sgslam/common/stats.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/map/map.h"
#include "sgslam/semantic/dynamic_mask.h"

namespace sgslam {

SE3 CurrentT_c_w(const KeyFrame& keyframe) {
  SE3 T_c_r;
  const KeyFrame* ref = &keyframe;
  while (ref->bad() && ref->parent_when_culled()) {
    T_c_r = T_c_r * ref->T_c_parent();
    ref = ref->parent_when_culled().get();
  }
  return T_c_r * ref->T_c_w();
}

SemanticMapper::SemanticMapper(const Config& config, const Map& map, bool sequential)
    : config_(config),
      map_(map),
      sequential_(sequential),
      camera_(std::make_shared<Camera>(config.camera)),
      rays_(*camera_),
      classes_(config.detector),
      octomap_(config.semantic),
      objects_(config.semantic,
               [cam = camera_](const Eigen::Vector3d& p_c) { return cam->Distort(cam->Project(p_c)); },
               cv::Size(config.camera.width, config.camera.height)) {
  if (!sequential_) thread_ = std::thread([this] { Loop(); });
}

SemanticMapper::~SemanticMapper() { Finish(); }

void SemanticMapper::Submit(SemanticInput input) {
  if (sequential_) {
    ProcessKeyFrame(input);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    if (stop_) return;
    if (queue_.size() >= static_cast<std::size_t>(config_.semantic.queue_size)) {
      queue_.pop_front();  // behind: the oldest keyframe's views are the most covered by later ones
      ++stats_.dropped;
    }
    queue_.push_back(std::move(input));
  }
  wake_.notify_one();
}

void SemanticMapper::Finish() {
  if (finished_) return;
  finished_ = true;
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void SemanticMapper::Loop() {
  for (;;) {
    SemanticInput input;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopped and drained
      input = std::move(queue_.front());
      queue_.pop_front();
    }
    ProcessKeyFrame(input);
  }
}

void SemanticMapper::ProcessKeyFrame(const SemanticInput& input) {
  const Stopwatch total;
  const SemanticConfig& c = config_.semantic;
  const KeyFrame& kf = *input.keyframe;
  const Features& f = *kf.features;
  SE3 T_w_c;
  {
    std::shared_lock lock(map_.mutex());
    T_w_c = CurrentT_c_w(kf).Inverse();
  }
  StageMs ms{};
  Stopwatch stage;
  const cv::Mat mask =
      DynamicPixelMask(input.depth, config_.camera.depth_factor, f.detections, classes_, f.keys, f.dynamic, c);
  ms.mask = stage.ElapsedMs();

  stage.Restart();
  clouds_.push_back({input.keyframe, VoxelDownsample(BackProject(input.bgr, input.depth, config_.camera.depth_factor,
                                                                 mask, rays_, c.cloud_stride, c),
                                                     c.cloud_voxel)});
  ms.cloud = stage.ElapsedMs();

  stage.Restart();
  octomap_.Insert(clouds_.back().points_c,
                  BackProject(input.bgr, input.depth, config_.camera.depth_factor, mask, rays_, c.octomap_stride, c),
                  T_w_c);
  ms.octomap = stage.ElapsedMs();

  stage.Restart();
  for (const Detection& d : f.detections) {
    // Sec. III-E: every detection except those of dynamic objects (people, dogs).
    if (classes_.is_dynamic(d.class_name) || d.score < c.object_min_score) continue;
    auto obs = ObserveObject(d, input.depth, config_.camera.depth_factor, rays_, c);
    if (!obs) continue;
    obs->keyframe = input.keyframe;
    const int b = c.object_border;
    const bool cut = d.box.x < b || d.box.y < b || d.box.x + d.box.width > input.depth.cols - b ||
                     d.box.y + d.box.height > input.depth.rows - b;
    objects_.Add(std::move(*obs), T_w_c, /*may_create=*/!cut);
  }
  ms.objects = stage.ElapsedMs();

  std::lock_guard lock(mutex_);
  ++stats_.keyframes;
  stats_.ms.push_back(total.ElapsedMs());
  stage_ms_.push_back(ms);
}

void SemanticMapper::ExportCloud(std::vector<Eigen::Vector3d>& points, std::vector<Rgb>& colours) {
  octomap_.Finalize();
  std::vector<ColoredPoint> world;
  for (const KeyFrameCloud& k : clouds_) {
    const SE3 T_w_c = CurrentT_c_w(*k.keyframe).Inverse();
    for (const ColoredPoint& p : k.points_c) world.push_back({(T_w_c * p.p.cast<double>()).cast<float>(), p.rgb});
  }
  const std::vector<ColoredPoint> merged = VoxelDownsample(world, config_.semantic.cloud_voxel);
  points.clear();
  colours.clear();
  std::size_t freed = 0;
  for (const ColoredPoint& p : merged) {
    const Eigen::Vector3d x = p.p.cast<double>();
    // A voxel that later views saw through held something that moved away.
    if (config_.semantic.free_space_filter && octomap_.IsFree(x)) {
      ++freed;
      continue;
    }
    points.push_back(x);
    colours.push_back(p.rgb);
  }
  std::lock_guard lock(mutex_);
  stats_.cloud_points = points.size();
  stats_.cloud_points_freed = freed;
}

SemanticMapper::CloudTruth SemanticMapper::ScoreCloud(const std::function<cv::Mat(Timestamp)>& mask_of) const {
  CloudTruth t;
  for (const KeyFrameCloud& k : clouds_) {
    const cv::Mat mask = mask_of(k.keyframe->t);
    if (mask.empty()) continue;
    ++t.keyframes;
    const SE3 T_w_c = CurrentT_c_w(*k.keyframe).Inverse();
    for (const ColoredPoint& p : k.points_c) {
      if (config_.semantic.free_space_filter && octomap_.IsFree(T_w_c * p.p.cast<double>())) continue;
      const Eigen::Vector2d uv = camera_->Distort(camera_->Project(p.p.cast<double>()));
      const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
      if (u < 0 || v < 0 || u >= mask.cols || v >= mask.rows) continue;
      ++t.points;
      t.moving += mask.at<std::uint8_t>(v, u) != 0;
    }
  }
  return t;
}

std::vector<ObjectEstimate> SemanticMapper::ExportObjects(const SE3& T_out_w) const {
  return objects_.Estimate([](const KeyFrame& kf) { return CurrentT_c_w(kf).Inverse(); }, T_out_w);
}

SemanticStats SemanticMapper::stats() const {
  std::lock_guard lock(mutex_);
  SemanticStats s = stats_;
  const auto median = [&](double StageMs::*field) {
    std::vector<double> v;
    for (const StageMs& m : stage_ms_) v.push_back(m.*field);
    return Median(std::move(v));
  };
  s.median_mask_ms = median(&StageMs::mask);
  s.median_cloud_ms = median(&StageMs::cloud);
  s.median_octomap_ms = median(&StageMs::octomap);
  s.median_objects_ms = median(&StageMs::objects);
  return s;
}

}  // namespace sgslam
