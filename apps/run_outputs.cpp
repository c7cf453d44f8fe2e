#include "run_outputs.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <sstream>

#include "map_plot.h"
#include "semantic_output.h"
#include "sgslam/common/stats.h"
#include "sgslam/common/error.h"
#include "sgslam/config/yaml_io.h"
#include "sgslam/detection/darknet_model.h"
#include "sgslam/detection/detections_file.h"
#include "sgslam/io/atomic_write.h"
#include "sgslam/io/ply.h"
#include "sgslam/loop/vocabulary_file.h"

namespace sgslam::app {

namespace {

nlohmann::json MedianOf(const std::vector<FrameReport>& reports, double FrameReport::*field) {
  std::vector<double> v;
  v.reserve(reports.size());
  for (const auto& r : reports) v.push_back(r.*field);
  return Median(std::move(v));
}

}  // namespace

std::string FailedOutputs::Joined() const {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

const std::vector<std::string>& RunOutputNames() {
  static const std::vector<std::string> kNames = {
      "trajectory.txt", "trajectory_online.txt", "keyframes.txt", "frames.csv",   "detections.txt",   "map_points.ply",
      "cloud.ply",      "octomap.bt",            "objects.json",  "map_top.png", "config_used.yaml", "stats.json",
      "tracks.txt"};
  return kNames;
}

const std::vector<std::string>& LiveOutputNames() {
  static const std::vector<std::string> kNames = {"cloud_live.ply", "octomap_live.bt"};
  return kNames;
}

void WriteConfigUsed(const std::filesystem::path& out, const Config& config, const std::string& source) {
  const std::string yaml = "# effective configuration of this run (source: " + source + ")\n" + ConfigToYaml(config);
  spdlog::debug("effective configuration:\n{}", yaml);
  WriteFileAtomically(out / "config_used.yaml", yaml);
}

void PlanRunOutputs(OutputPlan& plan, const Config& config, const std::filesystem::path& out, const std::string& role,
                    const std::filesystem::path& detections_dir) {
  plan.WritesFolder(out, role);
  for (const std::string& name : RunOutputNames()) plan.Writes(out / name, "the run's " + name);
  for (const std::string& name : LiveOutputNames()) plan.Writes(out / name, "the run's " + name);
  const DetectorConfig& d = config.detector;
  if (d.backend == "file") {
    plan.Reads(d.detections_file.empty() ? detections_dir / "detections.txt" : std::filesystem::path(d.detections_file),
               "the detections file of detector.backend file");
  } else if (d.backend == "dnn") {
    try {
      plan.ReadsFolder(ResolveModelDir(d.model_dir), "the detector's model folder");
    } catch (const Error&) {  // no model folder: loading the detector says so, before any frame
    }
  }
  if (config.loop.enabled) {
    try {
      plan.Reads(ResolveVocabulary(config.loop.vocabulary), "the vocabulary of loop.vocabulary");
    } catch (const Error&) {  // likewise, reported when it is loaded
    }
  }
}

RunMaps WriteSystemOutputs(const std::filesystem::path& out, SlamSystem& system, std::vector<FrameReport>& reports,
                           bool has_detector, bool print_objects, FailedOutputs& failed) {
  failed.Try("frames.csv", [&] { WriteFramesCsv(out / "frames.csv", reports); });
  if (has_detector) failed.Try("detections.txt", [&] { WriteDetections(out / "detections.txt", reports); });
  RunMaps maps;
  maps.trajectory = system.FrameTrajectory();
  failed.Try("trajectory.txt", [&] { WriteTumTrajectory(out / "trajectory.txt", maps.trajectory); });
  failed.Try("keyframes.txt", [&] { WriteTumTrajectory(out / "keyframes.txt", system.KeyFrameTrajectory()); });
  failed.Try("trajectory_online.txt",
             [&] { WriteTumTrajectory(out / "trajectory_online.txt", system.OnlineTrajectory()); });
  if (system.mover_tracker() != nullptr) {
    failed.Try("tracks.txt", [&] { movers::WriteTracksFile(out / "tracks.txt", system.MoverTracks()); });
  }
  const auto points = system.MapPointPositions();
  maps.map_points = points.size();
  failed.Try("map_points.ply", [&] { WritePly(out / "map_points.ply", points); });
  if (system.semantic() != nullptr) {
    const OutputWriter each = [&](const std::string& name, const std::function<void()>& write) {
      failed.Try(name, write);
    };
    failed.Try("the semantic map",
               [&] { maps.semantic = WriteSemanticMap(out, system, maps.trajectory, print_objects, each); });
  }
  return maps;
}

void RequestLiveOctoMap(const std::filesystem::path& out, SemanticMapper& semantic) {
  semantic.RequestOctoMap(out / "octomap_live.bt");
}

void WriteLiveOutputs(const std::filesystem::path& out, SlamSystem& system, const std::vector<FrameReport>& reports,
                      FailedOutputs& failed) {
  failed.Try("frames.csv", [&] { WriteFramesCsv(out / "frames.csv", reports); });
  failed.Try("trajectory.txt", [&] { WriteTumTrajectory(out / "trajectory.txt", system.FrameTrajectory()); });
  failed.Try("keyframes.txt", [&] { WriteTumTrajectory(out / "keyframes.txt", system.KeyFrameTrajectory()); });
  failed.Try("map_points.ply", [&] { WritePly(out / "map_points.ply", system.MapPointPositions()); });
  SemanticMapper* sem = system.semantic();
  if (sem == nullptr) return;
  const MapSnapshot map = system.SnapshotMap();
  failed.Try("cloud_live.ply", [&] {
    std::vector<Eigen::Vector3d> points;
    std::vector<Rgb> colours;
    for (const CloudPiece& piece : map.cloud) {
      if (!piece.points_c) continue;
      for (const ColoredPoint& p : *piece.points_c) {
        points.push_back(piece.T_w_c * p.p.cast<double>());
        colours.push_back(p.rgb);
      }
    }
    WritePly(out / "cloud_live.ply", points, colours);
  });
  failed.Try("objects.json",
             [&] { WriteObjectsJson(out / "objects.json", map.objects, sem->config().object_candidates); });
  RequestLiveOctoMap(out, *sem);
}

void WriteFramesCsv(const std::filesystem::path& path, const std::vector<FrameReport>& reports) {
  std::ostringstream csv;
  csv << "index,timestamp,state,features,kept,rejected_geometry,rejected_semantics,rejected_depth,detections,"
         "carried,followed,detector_late,matches,inliers,trusted,keyframe,map_keyframes,map_points,rss_mib,extract_ms,detector_ms,wait_ms,reject_ms,track_ms,total_ms,predicted,movers,movers_ms,budget_level\n";
  for (const auto& r : reports) {
    csv << r.index << ',' << FormatTimestamp(r.t) << ',' << ToString(r.state) << ',' << r.features << ',' << r.kept
        << ',' << r.rejected_geometry << ',' << r.rejected_semantics << ',' << r.rejected_depth << ','
        << r.detections << ',' << r.carried << ',' << r.followed << ',' << (r.detector_late ? 1 : 0) << ',' << r.matches << ','
        << r.inliers << ',' << r.trusted << ',' << (r.keyframe ? 1 : 0) << ',' << r.map_keyframes << ','
        << r.map_points << ',' << r.rss_mib << ',' << r.extract_ms << ','
        << r.detector_ms << ',' << r.wait_ms << ',' << r.reject_ms << ',' << r.track_ms << ',' << r.total_ms << ',' << r.predicted << ','
        << r.movers << ',' << r.movers_ms << ',' << r.budget_level << '\n';
  }
  WriteFileAtomically(path, csv.str());
}

void WriteDetections(const std::filesystem::path& path, std::vector<FrameReport>& reports) {
  std::vector<FrameDetections> boxes;
  for (auto& r : reports) {
    if (!r.boxes.empty()) boxes.emplace_back(r.t, std::move(r.boxes));
  }
  WriteDetectionsFile(path, boxes);
}

nlohmann::json WriteSemanticMap(const std::filesystem::path& out, SlamSystem& system, const Trajectory& trajectory,
                                bool print_objects, const OutputWriter& write_output) {
  SemanticMapper* sem = system.semantic();
  std::vector<Eigen::Vector3d> cloud;
  std::vector<Rgb> colours;
  std::vector<ObjectEstimate> objects;
  system.ExportSemantic(cloud, colours, objects);
  write_output("cloud.ply", [&] { WritePly(out / "cloud.ply", cloud, colours); });
  write_output("octomap.bt", [&] { sem->octomap().Write(out / "octomap.bt"); });
  write_output("objects.json",
               [&] { WriteObjectsJson(out / "objects.json", objects, sem->config().object_candidates); });
  write_output("map_top.png", [&] { WriteTopView(out / "map_top.png", cloud, colours, objects, trajectory); });
  if (print_objects) PrintObjectTable(objects);
  const SemanticStats st = sem->stats();
  if (st.dropped > 0) spdlog::warn("semantic mapping fell behind: {} keyframes left out of the map", st.dropped);
  return {{"keyframes", st.keyframes},
          {"keyframes_dropped", st.dropped},
          {"median_keyframe_ms", Median(st.ms)},
          {"median_detect_ms", st.median_detect_ms},
          {"keyframe_model_keyframes", st.model_keyframes},
          {"median_mask_ms", st.median_mask_ms},
          {"median_cloud_ms", st.median_cloud_ms},
          {"median_octomap_ms", st.median_octomap_ms},
          {"median_objects_ms", st.median_objects_ms},
          {"cloud_points", st.cloud_points},
          {"cloud_points_removed_as_free", st.cloud_points_freed},
          {"cloud_points_removed_as_seen_through", sem->inconsistent_points()},
          {"cloud_points_removed_as_seen_moving", sem->seen_moving_points()},
          {"cloud_points_removed_as_seen_once", sem->unsupported_points()},
          {"octomap_occupied_leaves", sem->octomap().OccupiedLeaves()},
          {"objects", std::count_if(objects.begin(), objects.end(), [](const auto& e) { return e.exported; })},
          {"object_candidates", std::count_if(objects.begin(), objects.end(), [](const auto& e) { return !e.exported; })},
          {"objects_removed", sem->objects_removed()}};
}

namespace {

double MedianFrameMs(const std::vector<FrameReport>& reports) {
  return MedianOf(reports, &FrameReport::total_ms).get<double>();
}

nlohmann::json MedianMsJson(const std::vector<FrameReport>& reports, double median_frame_ms) {
  return {{"extract", MedianOf(reports, &FrameReport::extract_ms)},
          {"detector", MedianOf(reports, &FrameReport::detector_ms)},
          {"detector_wait", MedianOf(reports, &FrameReport::wait_ms)},
          {"reject", MedianOf(reports, &FrameReport::reject_ms)},
          {"track", MedianOf(reports, &FrameReport::track_ms)},
          {"frame", median_frame_ms}};
}

// stats.json's tracks: the mover tracker's counts and cost (movers/mover_tracker.h).
nlohmann::json TracksJson(const std::vector<FrameReport>& reports, const movers::MoverTracker& tracker) {
  const movers::TrackerStats& s = tracker.stats();
  std::vector<double> ms;
  double predicted = 0, confirmed = 0;
  for (const FrameReport& r : reports) {
    ms.push_back(r.movers_ms);
    predicted += r.predicted;
    confirmed += r.movers;
  }
  const double n = std::max<double>(1.0, static_cast<double>(reports.size()));
  return {{"started", s.tracks},
          {"confirmed", s.confirmed},
          {"observations", {{"boxes", s.box_observations}, {"clusters", s.cluster_observations}}},
          {"confirmed_per_frame", confirmed / n},
          {"predicted_boxes_per_frame", predicted / n},
          {"median_ms", Median(ms)},
          {"p95_ms", Percentile(ms, 0.95)}};
}

nlohmann::json DynamicJson(const std::vector<FrameReport>& reports, const SlamSystem& system) {
  std::size_t late = 0;
  double rejected = 0, features = 0;
  for (const auto& r : reports) {
    late += r.detector_late ? 1 : 0;
    rejected += r.features - r.kept;
    features += r.features;
  }
  const DetectionWorkerStats d = system.detector_stats();
  return {{"rejected_share", features > 0 ? rejected / features : 0.0},
          {"detector", system.DescribeDetector()},
          {"detector_late_frames", late},
          {"detector_submitted", d.submitted},
          {"detector_share", reports.empty() ? 0.0 : static_cast<double>(d.submitted) / reports.size()},
          {"detector_processed", d.processed},
          {"detector_dropped", d.dropped},
          {"detector_errors", d.errors}};
}

nlohmann::json LocalMappingJson(const SlamSystem& system) {
  const auto mapping = system.mapping_stats();
  const auto median = [&](auto field) {
    std::vector<double> v;
    for (const auto& m : mapping) v.push_back(static_cast<double>(m.*field));
    return Median(std::move(v));
  };
  const auto full = system.map_full_at();
  return {{"keyframes_processed", mapping.size()},
          {"map_full_at_frame", full ? nlohmann::json(*full) : nlohmann::json(nullptr)},
          {"median_ms", median(&MappingStats::ms)},
          {"median_insert_ms", median(&MappingStats::insert_ms)},
          {"median_triangulate_ms", median(&MappingStats::triangulate_ms)},
          {"median_fuse_ms", median(&MappingStats::fuse_ms)},
          {"median_ba_ms", median(&MappingStats::ba_ms)},
          {"median_cull_ms", median(&MappingStats::cull_ms)},
          {"median_ba_keyframes", median(&MappingStats::local_keyframes)},
          {"median_ba_points", median(&MappingStats::local_points)}};
}

nlohmann::json GlobalBaJson(const SlamSystem& system) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& g : system.global_ba_reports()) {
    out.push_back({{"keyframes", g.keyframes}, {"points", g.points}, {"ms", g.ms}, {"applied", !g.aborted}});
  }
  return out;
}

nlohmann::json LoopJson(const std::vector<FrameReport>& reports, const SlamSystem& system) {
  int relocalised = 0;
  for (std::size_t i = 1; i < reports.size(); ++i) {
    relocalised += reports[i - 1].state == TrackState::kLost && reports[i].state == TrackState::kOk;
  }
  const std::vector<LoopReport> loops = system.loop_reports();
  int rejected = 0, consistent = 0, implausible = 0;
  std::vector<double> detect_ms;
  nlohmann::json closed = nlohmann::json::array();
  for (const LoopReport& r : loops) {
    rejected += r.rejected;
    implausible += r.implausible;
    consistent += r.consistent;
    detect_ms.push_back(r.detect_ms);
    if (!r.closed) continue;
    closed.push_back({{"keyframe", r.keyframe},
                      {"loop_keyframe", r.loop_keyframe},
                      {"timestamp", FormatTimestamp(r.t)},
                      {"loop_timestamp", FormatTimestamp(r.loop_t)},
                      {"inliers", r.inliers},
                      {"moved_m", r.correction_m},
                      {"turned_deg", r.correction_deg},
                      {"fused_points", r.fused},
                      {"graph_keyframes", r.corrected_keyframes},
                      {"pose_graph_ms", r.pose_graph_ms},
                      {"correction_ms", r.correct_ms}});
  }
  return {{"place_recognition", system.place_recognition()},
          {"relocalisations", relocalised},
          {"keyframes_checked", loops.size()},
          {"consistent_candidates", consistent},
          {"loops_rejected", rejected},
          {"loops_rejected_as_beyond_drift", implausible},
          {"loops_closed", closed.size()},
          {"median_detect_ms", Median(std::move(detect_ms))},
          {"closed", closed},
          {"global_ba", GlobalBaJson(system)}};
}

// The frames whose pose came from the odometry fallback (TrackState::kOdometry): how
// many, in how many stretches, the longest, and how many stretches ended back in the map.
nlohmann::json OdometryJson(const std::vector<FrameReport>& reports) {
  int frames = 0, stretches = 0, longest = 0, rejoined = 0, run = 0;
  for (std::size_t i = 0; i < reports.size(); ++i) {
    if (reports[i].state != TrackState::kOdometry) continue;
    ++frames;
    run = i > 0 && reports[i - 1].state == TrackState::kOdometry ? run + 1 : 1;
    stretches += run == 1;
    longest = std::max(longest, run);
    rejoined += i + 1 < reports.size() && reports[i + 1].state == TrackState::kOk;
  }
  return {{"frames", frames}, {"stretches", stretches}, {"longest", longest}, {"rejoined", rejoined}};
}

}  // namespace

RunTotals TotalsOf(const std::vector<FrameReport>& reports, const SlamSystem& system, std::size_t map_points) {
  RunTotals t;
  t.frames = reports.size();
  for (const FrameReport& r : reports) {
    t.tracked += r.state == TrackState::kOk;
    t.odometry += r.state == TrackState::kOdometry;
    t.lost += r.state == TrackState::kLost;
  }
  t.keyframes = system.NumKeyFrames();
  t.map_points = map_points;
  t.median_frame_ms = MedianFrameMs(reports);
  t.peak_rss_mib = PeakRssMiB();
  return t;
}

nlohmann::json SystemStatsJson(const Config& config, const RunTotals& totals, const std::vector<FrameReport>& reports,
                               const SlamSystem& system) {
  nlohmann::json stats = {{"mode", config.dynamic.mode},
                          {"frames", totals.frames},
                          {"tracked", totals.tracked},
                          {"odometry", OdometryJson(reports)},
                          {"lost", totals.lost},
                          {"keyframes", totals.keyframes},
                          {"map_points", totals.map_points},
                          {"median_ms", MedianMsJson(reports, totals.median_frame_ms)},
                          {"peak_rss_mib", totals.peak_rss_mib},
                          {"dynamic", DynamicJson(reports, system)},
                          {"local_mapping", LocalMappingJson(system)},
                          {"loop", LoopJson(reports, system)}};
  if (const movers::MoverTracker* tracker = system.mover_tracker()) stats["tracks"] = TracksJson(reports, *tracker);
  if (const CpuBudget& b = system.cpu_budget(); b.enabled()) {
    std::vector<double> levels;
    for (const FrameReport& r : reports) levels.push_back(r.budget_level);
    stats["budget"] = {{"cores", b.cores()},
                       {"windows", b.windows()},
                       {"windows_over", b.windows_over()},
                       {"level_max", b.max_level_reached()},
                       {"level_median", Median(std::move(levels))},
                       {"last_cores_used", b.last_usage() ? nlohmann::json(*b.last_usage()) : nlohmann::json(nullptr)}};
  }
  if (const auto& gba = system.final_ba(); gba && gba->local_keyframes > 0) {
    spdlog::info("final bundle adjustment: {} keyframes, {} points, {:.2f} s", gba->local_keyframes, gba->local_points,
                 gba->ms / 1000.0);
    stats["final_ba"] = {{"ms", gba->ms}, {"keyframes", gba->local_keyframes}, {"points", gba->local_points}};
  }
  return stats;
}

void WriteStatsJson(const std::filesystem::path& out, nlohmann::json stats, const nlohmann::json& semantic,
                    const std::string& ended, const std::string& failure, FailedOutputs& failed) {
  if (!semantic.is_null()) stats["semantic"] = semantic;
  if (!failure.empty()) stats["error"] = failure;
  stats["ended"] = failure.empty() ? ended : "failed: " + failure;
  if (!failed.names.empty()) stats["failed_outputs"] = failed.names;
  failed.Try("stats.json", [&] { WriteFileAtomically(out / "stats.json", stats.dump(2) + "\n"); });
}

nlohmann::json LiveJson(std::size_t dropped, const std::vector<double>& latency_ms) {
  return {{"dropped", dropped},
          {"median_latency_ms", Median(latency_ms)},
          {"p95_latency_ms", Percentile(latency_ms, 0.95)},
          {"max_latency_ms", Percentile(latency_ms, 1.0)}};
}

}  // namespace sgslam::app
