#include "live_source.h"

#include <algorithm>
#include <chrono>

#include <opencv2/imgcodecs.hpp>
#include <spdlog/spdlog.h>

#include "message.h"
#include "movers.h"
#include "sgslam/semantic/object_json.h"
#include "truth.h"
#include "sgslam/common/time.h"

namespace sgslam::viewer {

namespace {

double SteadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The cloud: every piece's pose; the points of the pieces the page lacks (ids above
// pieces_after), an even subsample of at most kMaxPiecePoints each.
void AddCloudPieces(const std::vector<CloudPiece>& cloud, std::int64_t pieces_after, MessageBuilder& m) {
  std::vector<std::uint32_t> piece_ids, new_ids, new_counts;
  std::vector<float> piece_poses, xyz;
  std::vector<std::uint8_t> rgb;
  for (const CloudPiece& piece : cloud) {
    piece_ids.push_back(static_cast<std::uint32_t>(piece.keyframe_id));
    const std::vector<float> T = ColumnMajor(piece.T_w_c);
    piece_poses.insert(piece_poses.end(), T.begin(), T.end());
    if (static_cast<std::int64_t>(piece.keyframe_id) <= pieces_after || !piece.points_c) continue;
    const std::vector<ColoredPoint>& pts = *piece.points_c;
    const std::size_t step = (pts.size() + LiveSource::kMaxPiecePoints - 1) / LiveSource::kMaxPiecePoints;
    std::uint32_t n = 0;
    for (std::size_t i = 0; i < pts.size(); i += std::max<std::size_t>(step, 1), ++n) {
      xyz.insert(xyz.end(), {pts[i].p.x(), pts[i].p.y(), pts[i].p.z()});
      rgb.insert(rgb.end(), {pts[i].rgb[0], pts[i].rgb[1], pts[i].rgb[2]});
    }
    new_ids.push_back(static_cast<std::uint32_t>(piece.keyframe_id));
    new_counts.push_back(n);
  }
  m.Add("piece_ids", piece_ids);
  m.Add("piece_poses", piece_poses);
  m.Add("new_piece_ids", new_ids);
  m.Add("new_piece_counts", new_counts);
  m.Add("new_piece_xyz", xyz);
  m.Add("new_piece_rgb", rgb);
}


}  // namespace

void LiveSource::AddFrame(const FrameReport& report) {
  const auto snapshot = system_.LatestFrame();
  {
    std::lock_guard lock(mutex_);
    ++version_;
    if (report.state == TrackState::kOk && last_state_ == TrackState::kLost) relocalised_at_ = report.index;
    last_state_ = report.state;
    if (snapshot && snapshot->index == report.index && snapshot->T_w_c) {
      const Eigen::Vector3d p = snapshot->T_w_c->translation();
      path_.insert(path_.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
    }
    arrivals_.push_back(SteadySeconds());
    if (arrivals_.size() > 30) arrivals_.pop_front();
    keyframes_ = report.map_keyframes;
    map_points_ = report.map_points;
    kept_ = report.kept;
    rejected_ = report.rejected_geometry + report.rejected_semantics + report.rejected_depth;
  }
  if (server_) server_->NotifyFrame();
}

std::uint64_t LiveSource::FrameVersion() const {
  std::lock_guard lock(mutex_);
  return version_;
}

std::shared_ptr<const std::string> LiveSource::EncodeFrame() {
  const auto f = system_.LatestFrame();
  if (!f) return nullptr;
  MessageBuilder m("frame");
  nlohmann::json& h = m.header();
  h["index"] = f->index;
  h["t"] = ToSeconds(f->t);
  h["state"] = ToString(f->state);
  {
    std::lock_guard lock(mutex_);
    h["version"] = version_;
    h["keyframes"] = keyframes_;
    h["map_points"] = map_points_;
    const int judged = kept_ + rejected_;
    h["rejected_share"] = judged > 0 ? static_cast<double>(rejected_) / judged : 0.0;
    h["fps"] = arrivals_.size() > 1 ? (arrivals_.size() - 1) / (arrivals_.back() - arrivals_.front()) : 0.0;
    // Shown for a second or two after the track came back.
    if (relocalised_at_ && f->state == TrackState::kOk && f->index < *relocalised_at_ + kShowRelocalisedFrames) {
      h["state"] = "relocalised at frame " + std::to_string(*relocalised_at_ + 1);
    }
  }
  h["keyframe"] = f->keyframe;
  h["frame_ms"] = f->frame_ms;
  h["paused"] = pause_.paused();
  if (f->T_w_c) h["pose"] = ColumnMajor(*f->T_w_c);
  h["detections"] = nlohmann::json::array();
  for (const Detection& d : f->detections) {
    h["detections"].push_back({{"name", d.class_name},
                               {"score", d.score},
                               {"box", {d.box.x, d.box.y, d.box.width, d.box.height}},
                               {"carried", d.carried}});
  }
  h["movers"] = MoversJson(f->movers);
  std::vector<std::uint8_t> jpeg;
  if (!f->bgr.empty()) cv::imencode(".jpg", f->bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, 75});
  m.Add("image", jpeg);
  std::vector<float> xy;
  xy.reserve(2 * f->keypoints.size());
  for (const cv::Point2f& p : f->keypoints) xy.insert(xy.end(), {p.x, p.y});
  m.Add("keypoints", xy);
  m.Add("labels", f->labels);
  return m.Finish();
}

std::shared_ptr<const std::string> LiveSource::EncodeMap(const MapRequest& request) {
  const MapSnapshot map = system_.SnapshotMap();
  MessageBuilder m("map");
  if (map.cells && map.cells != cells_) {
    cells_ = map.cells;
    ++cells_version_;
  }
  m.header()["cells_version"] = cells_version_;
  // Also here, not only with the frames: a paused run sends no new frame, and the
  // pages learn of a pause or resume from another page by the map.
  m.header()["paused"] = pause_.paused();
  if (cells_ && request.cells_have != cells_version_) {
    std::vector<float> cells;
    cells.reserve(4 * cells_->size());
    for (const Eigen::Vector4f& c : *cells_) cells.insert(cells.end(), {c.x(), c.y(), c.z(), c.w()});
    m.Add("cells", cells);
  }
  std::vector<std::uint32_t> kf_ids;
  std::vector<float> kf_poses;
  for (const KeyFramePose& k : map.keyframes) {
    kf_ids.push_back(static_cast<std::uint32_t>(k.id));
    const std::vector<float> T = ColumnMajor(k.T_w_c);
    kf_poses.insert(kf_poses.end(), T.begin(), T.end());
  }
  m.Add("keyframe_ids", kf_ids);
  m.Add("keyframe_poses", kf_poses);
  if (!truth_.empty()) {
    Trajectory keyframes;
    for (const KeyFramePose& k : map.keyframes) keyframes.push_back({k.t, k.T_w_c});
    std::sort(keyframes.begin(), keyframes.end(), [](const auto& a, const auto& b) { return a.t < b.t; });
    m.Add("truth", AlignedTruth(truth_, keyframes));
  }
  std::vector<float> points;
  points.reserve(3 * map.points.size());
  for (const Eigen::Vector3d& p : map.points) {
    points.insert(points.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
  }
  m.Add("points", points);
  {
    std::lock_guard lock(mutex_);
    m.Add("path", path_);
  }
  AddCloudPieces(map.cloud, request.pieces_after, m);
  m.header()["objects"] = ObjectsJson(map.objects);
  return m.Finish();
}

nlohmann::json LiveSource::Info() const {
  nlohmann::json info = info_;
  info["paused"] = pause_.paused();
  return info;
}

bool LiveSource::Control(const std::string& what, std::uint64_t page) {
  if (what == "pause") {
    pause_.Pause(page);
  } else if (what == "resume") {
    pause_.Resume();
  } else if (what == "step") {
    pause_.Step(page);
  } else {
    return false;
  }
  return true;
}

void LiveSource::PageClosed(std::uint64_t page) {
  if (pause_.Release(page)) spdlog::info("viewer: the last page that held the pause has closed; the run goes on");
}

}  // namespace sgslam::viewer
