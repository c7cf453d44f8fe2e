#include "truth_scorer.h"

#include <spdlog/spdlog.h>

#include "sgslam/eval/semantic_score.h"

namespace sgslam::app {

void TruthScorer::AddFrame(const FrameReport& report) {
  if (auto mask = masks_.Load(report.t)) rejection_.Add(eval::ScoreKeypoints(*mask, report.keypoints, report.rejected));
}

nlohmann::json TruthScorer::RejectionJson() const {
  const eval::MaskScore& t = rejection_;
  if (t.frames == 0) return nullptr;
  spdlog::info("dynamic rejection vs ground-truth masks ({} frames): {:.1f} % of {} moving keypoints rejected, "
               "{:.1f} % of {} static keypoints lost ({:.1f} % of those {} px or more from a mover), precision {:.1f} %",
               t.frames, 100 * t.recall(), t.moving, 100 * t.static_loss(), t.static_points,
               100 * t.static_loss_away(), eval::MaskScore::kOutlinePx, 100 * t.precision());
  return {{"frames", t.frames},
          {"moving_keypoints", t.moving},
          {"moving_rejected", t.moving_rejected},
          {"recall", t.recall()},
          {"static_keypoints", t.static_points},
          {"static_rejected", t.static_rejected},
          {"static_loss", t.static_loss()},
          {"static_near_movers", t.static_near},
          {"static_near_movers_rejected", t.static_near_rejected},
          {"static_loss_away_from_movers", t.static_loss_away()},
          {"near_movers_px", eval::MaskScore::kOutlinePx},
          {"precision", t.precision()}};
}

nlohmann::json TruthScorer::SemanticJson(const SemanticMapper& map, const TumDataset& dataset,
                                         const CameraConfig& camera) const {
  if (!active()) return nullptr;
  const auto mask_of = [&](Timestamp t) { return masks_.Load(t).value_or(cv::Mat()); };
  const eval::CloudTruth cloud = eval::ScoreCloud(map, mask_of);
  const double share = cloud.points > 0 ? static_cast<double>(cloud.moving) / cloud.points : 0.0;
  nlohmann::json out = {{"keyframes", cloud.keyframes},
                        {"cloud_points", cloud.points},
                        {"cloud_points_on_moving_pixels", cloud.moving},
                        {"moving_share", share}};
  spdlog::info("dense cloud vs ground-truth masks ({} keyframes): {:.2f} % of {} points on moving pixels",
               cloud.keyframes, 100 * share, cloud.points);
  std::unordered_map<Timestamp, std::size_t> index_of;
  for (std::size_t i = 0; i < dataset.size(); ++i) index_of[dataset.frames()[i].t_rgb] = i;
  const auto depth_of = [&](Timestamp t) {
    const auto it = index_of.find(t);
    return it == index_of.end() ? cv::Mat() : dataset.Load(it->second, camera).depth;
  };
  const eval::OctoMapTruth octomap = eval::ScoreOctoMap(map, mask_of, depth_of);
  const double occupied = octomap.path_cells > 0 ? static_cast<double>(octomap.occupied) / octomap.path_cells : 0.0;
  out["octomap_path_cells"] = octomap.path_cells;
  out["octomap_path_cells_occupied"] = octomap.occupied;
  out["octomap_path_occupied_share"] = occupied;
  if (octomap.path_cells > 0) {
    spdlog::info("OctoMap vs ground-truth masks: {} of {} cells on the movers' paths occupied ({:.2f} %)",
                 octomap.occupied, octomap.path_cells, 100 * occupied);
  }
  return out;
}

}  // namespace sgslam::app
