// SlamSystem's map reuse: saving the live map and starting from a saved one.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <optional>

#include "sgslam/common/error.h"
#include "sgslam/common/stats.h"
#include "sgslam/mapfile/map_capture.h"
#include "sgslam/mapfile/map_file.h"
#include "sgslam/system/slam_system.h"
#include "sgslam/tracking/trusted_pose.h"

namespace sgslam {

namespace {

mapfile::Settings SettingsOf(const Config& config, const KeyFrameDatabase* places) {
  return mapfile::RunSettings(config.camera, config.orb.scale_factor, config.orb.levels,
                              places ? places->vocabulary().checksum() : std::string());
}

}  // namespace

void SlamSystem::LoadMap(const mapfile::MapData& data, const std::string& what) {
  if (next_frame_id_ != 0 || !map_.keyframes().empty()) {
    throw std::logic_error("SlamSystem::LoadMap: only before the first frame");
  }
  mapfile::CheckCompatible(data.settings, SettingsOf(config_, places_.get()), what);
  SemanticState semantic = mapfile::RestoreMap(data, map_, camera_, scale_);
  std::uint64_t next_frame = data.next_frame_id;
  {
    std::unique_lock lock(map_.mutex());
    for (const auto& [id, kf] : map_.keyframes()) {
      // Keyframes saved before local mapping had them: described now.
      if (!kf->bow) kf->bow = places_->Describe(kf->features->descriptors);
      places_->Add(kf);
      next_frame = std::max(next_frame, kf->frame_id + 1);
    }
  }
  // The loaded points have stood the test of the run that made them (and trust's
  // clock, the points' creation times, may be later than this run's frames).
  std::vector<std::shared_ptr<MapPoint>> points;
  for (const auto& [id, p] : map_.map_points()) points.push_back(p);
  TrustAll(points);
  next_frame_id_ = next_frame;
  last_keyframe_frame_id_ = next_frame;
  if (semantic_) semantic_->Restore(std::move(semantic));
  tracker_.StartInMap();
  spdlog::info("map {} loaded: {} keyframes, {} map points{}", what, map_.keyframes().size(), map_.map_points().size(),
               data.semantic.present ? ", " + std::to_string(data.semantic.objects.size()) + " objects" : "");
}

bool SlamSystem::SaveMap(const std::filesystem::path& path) {
  if (NumKeyFrames() == 0) {
    spdlog::warn("map not saved to {}: the map is empty (no frame was tracked)", path.string());
    return false;
  }
  if (saving_.exchange(true)) {
    spdlog::warn("map save to {} refused: the previous save is still being written", path.string());
    return false;
  }
  const std::uint64_t next_frame = next_frame_id_;
  const bool now = sequential_ || finished_;
  if (semantic_) {
    semantic_->RequestState([this, path, next_frame, now](SemanticState state) {
      SaveCaptured(path, std::move(state), next_frame, now);
    });
  } else {
    SaveCaptured(path, std::nullopt, next_frame, now);
  }
  return true;
}

void SlamSystem::SaveCaptured(const std::filesystem::path& path, std::optional<SemanticState> semantic,
                              std::uint64_t next_frame_id, bool now) {
  // The map is copied here, not on the (lowest-priority) semantic thread, which
  // could be preempted while it holds the map's lock. Nothing may escape (on the
  // saver thread it would end the process), and saving_ ends false.
  auto save = [this, path, semantic = std::move(semantic), next_frame_id] {
    try {
      const Stopwatch copy;
      const mapfile::MapData data = mapfile::CaptureMap(map_, SettingsOf(config_, places_.get()), next_frame_id,
                                                        semantic ? &*semantic : nullptr);
      const double copy_ms = copy.ElapsedMs();
      const Stopwatch watch;
      mapfile::WriteMapFile(path, data);
      ++maps_saved_;
      const auto live = std::count_if(data.keyframes.begin(), data.keyframes.end(),
                                      [](const mapfile::KeyFrameData& k) { return !k.culled; });
      spdlog::info("map saved to {}: {} keyframes, {} points (copied in {:.0f} ms, written in {:.0f} ms)",
                   path.string(), live, data.points.size(), copy_ms, watch.ElapsedMs());
    } catch (const std::exception& e) {
      spdlog::error("map not saved to {}: {}", path.string(), e.what());
    }
    saving_ = false;
  };
  if (now) {
    save();
    return;
  }
  std::lock_guard lock(save_mutex_);  // the previous save's thread is already done (saving_ was false)
  if (!saver_.Run(true, std::move(save))) spdlog::warn("no thread for the map save: it was written here");
}

}  // namespace sgslam
