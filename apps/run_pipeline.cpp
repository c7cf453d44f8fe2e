#include "run_pipeline.h"

#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <optional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <unordered_map>

#include "progress.h"
#include "sgslam/common/error.h"
#include "sgslam/common/stats.h"
#include "sgslam/config/yaml_io.h"
#include "sgslam/eval/ate.h"
#include "sgslam/eval/mask_score.h"
#include "sgslam/eval/semantic_score.h"
#include "sgslam/detection/detections_file.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/io/ply.h"
#include "sgslam/io/text_file.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/detection/detector.h"
#include "sgslam/system/run_config.h"
#include "sgslam/system/slam_system.h"
#include "map_plot.h"
#include "semantic_output.h"

namespace sgslam::app {

namespace fs = std::filesystem;

namespace {

std::atomic<bool> g_interrupted{false};
std::atomic<bool> g_octomap_requested{false};
extern "C" void OnInterrupt(int) { g_interrupted = true; }
extern "C" void OnOctoMapRequest(int) { g_octomap_requested = true; }

// Restores the previous SIGINT and SIGUSR1 handlers on scope exit. SIGUSR1
// (`kill -USR1 <pid>`) asks for the OctoMap built so far, in octomap.bt.
class InterruptGuard {
 public:
  InterruptGuard()
      : previous_(std::signal(SIGINT, OnInterrupt)), previous_usr1_(std::signal(SIGUSR1, OnOctoMapRequest)) {
    g_interrupted = false;
    g_octomap_requested = false;
  }
  ~InterruptGuard() {
    std::signal(SIGINT, previous_);
    std::signal(SIGUSR1, previous_usr1_);
  }

 private:
  void (*previous_)(int);
  void (*previous_usr1_)(int);
};

nlohmann::json MedianOf(const std::vector<FrameReport>& reports, double FrameReport::*field) {
  std::vector<double> v;
  v.reserve(reports.size());
  for (const auto& r : reports) v.push_back(r.*field);
  return Median(std::move(v));
}

}  // namespace

RunSummary RunSequence(const RunOptions& o) {
  const fs::path dataset_dir = o.dataset;
  RunConfig rc = ResolveRunConfig(o.config.empty() ? std::nullopt : std::optional<fs::path>(o.config), dataset_dir);
  // Command-line options override the file; the result is validated again.
  if (!o.mode.empty()) rc.config.dynamic.mode = o.mode;
  if (!o.model.empty()) rc.config.detector.model_dir = o.model;
  if (o.no_detector) rc.config.detector.backend = "none";
  const bool options = !o.mode.empty() || !o.model.empty() || o.no_detector;
  if (options) rc.source += " + command-line options";
  if (o.tweak) {
    o.tweak(rc.config);
    rc.source += " + " + (o.tweak_name.empty() ? std::string("program overrides") : o.tweak_name);
  }
  if (options || o.tweak) rc.config.Validate(rc.source);
  const Config& config = rc.config;
  TumDataset dataset(dataset_dir, config.dataset);
  RunSummary s;
  s.out = o.out.empty() ? fs::path("sgslam-out") / dataset.name() : fs::path(o.out);
  std::error_code ec;
  fs::create_directories(s.out, ec);
  if (ec || !fs::is_directory(s.out)) throw InputError("cannot create output folder " + s.out.string());

  spdlog::info("dataset {}: {} RGB-D frames ({}), config: {}", dataset.dir().string(), dataset.size(),
               dataset.associations_from_file() ? "associations.txt" : "associated by timestamp", rc.source);
  const std::string yaml = "# effective configuration of this run (source: " + rc.source + ")\n" + ConfigToYaml(config);
  spdlog::debug("effective configuration:\n{}", yaml);
  WriteFileAtomically(s.out / "config_used.yaml", yaml);
  if (o.viewer_port != 0) spdlog::warn("--viewer is not built yet; ignored");

  // The detector is loaded before any thread starts, so a missing or broken model
  // is reported at once; only the modes that use boxes need one.
  std::unique_ptr<Detector> detector;
  const bool uses_boxes = config.dynamic.mode == "semantic" || config.dynamic.mode == "sg";
  if (uses_boxes) detector = MakeDetector(config.detector, dataset_dir);
  const bool has_detector = detector != nullptr;
  SlamSystem system(config, o.sequential, std::move(detector));
  spdlog::info("mode {}, detector: {}", config.dynamic.mode, system.DescribeDetector());
  if (config.camera.readout > 0) {
    spdlog::info("rolling shutter: rows read out over {:.0f} ms (camera.readout; 0 for a global shutter)",
                 1000 * config.camera.readout);
  }
  std::vector<FrameReport> reports;
  const eval::MaskIndex masks(dataset_dir);  // ground-truth dynamic masks, when the sequence has them
  eval::MaskScore truth;
  std::string failure;
  Stopwatch wall;
  {
    InterruptGuard guard;
    FrameStream stream(dataset, config.camera, static_cast<std::size_t>(config.dataset.prefetch), o.max_frames);
    ProgressBar progress(stream.size());
    const auto start = std::chrono::steady_clock::now();
    Timestamp t_first = 0;
    try {
      while (auto frame = stream.Next()) {
        if (o.realtime) {  // wait for the frame's time; a late frame goes at once (none is dropped)
          if (reports.empty()) t_first = frame->t;
          std::this_thread::sleep_until(start + std::chrono::nanoseconds(frame->t - t_first));
        }
        if (reports.empty()) CheckDepthScale(*frame, dataset.frames()[frame->index], config.camera, config.dataset);
        reports.push_back(system.Process(*frame));
        FrameReport& r = reports.back();
        if (auto mask = masks.Load(r.t)) {
          truth.Add(eval::ScoreKeypoints(*mask, r.keypoints, r.rejected));
        }
        r.keypoints = {};  // keep the per-frame record small
        r.rejected = {};
        progress.Update(reports.size(), reports.size() / (wall.ElapsedMs() * 1e-3));
        if (g_octomap_requested.exchange(false)) {
          if (SemanticMapper* sem = system.semantic()) {
            sem->RequestOctoMap(s.out / "octomap.bt");
          } else {
            spdlog::warn("OctoMap requested (SIGUSR1), but the semantic thread is off (semantic.enabled)");
          }
        }
        if (g_interrupted) {
          spdlog::warn("interrupted: writing the outputs of the {} frames processed", reports.size());
          break;
        }
      }
    } catch (const Error& e) {
      if (reports.empty()) throw;
      failure = e.what();  // save what was done, then report
    }
  }
  system.Finish();
  const double seconds = wall.ElapsedMs() * 1e-3;

  std::ostringstream csv;
  csv << "index,timestamp,state,features,kept,rejected_geometry,rejected_semantics,rejected_depth,detections,"
         "carried,detector_late,matches,inliers,trusted,keyframe,extract_ms,detector_ms,wait_ms,reject_ms,track_ms,total_ms\n";
  for (const auto& r : reports) {
    csv << r.index << ',' << FormatTimestamp(r.t) << ',' << ToString(r.state) << ',' << r.features << ',' << r.kept
        << ',' << r.rejected_geometry << ',' << r.rejected_semantics << ',' << r.rejected_depth << ','
        << r.detections << ',' << r.carried << ',' << (r.detector_late ? 1 : 0) << ',' << r.matches << ',' << r.inliers << ',' << r.trusted << ','
        << (r.keyframe ? 1 : 0) << ',' << r.extract_ms << ',' << r.detector_ms << ',' << r.wait_ms << ','
        << r.reject_ms << ',' << r.track_ms << ',' << r.total_ms << '\n';
    s.tracked += r.state == TrackState::kOk;
    s.lost += r.state == TrackState::kLost;
  }
  WriteFileAtomically(s.out / "frames.csv", csv.str());
  if (has_detector) {
    // In the format of the file backend (io/detections_file.h): a later run can
    // replay them with detector.backend: file, detector.detections_file: this file.
    std::vector<FrameDetections> boxes;
    for (auto& r : reports) {
      if (!r.boxes.empty()) boxes.emplace_back(r.t, std::move(r.boxes));
    }
    WriteDetectionsFile(s.out / "detections.txt", boxes);
  }
  const Trajectory trajectory = system.FrameTrajectory();
  WriteTumTrajectory(s.out / "trajectory.txt", trajectory);
  WriteTumTrajectory(s.out / "keyframes.txt", system.KeyFrameTrajectory());
  WriteTumTrajectory(s.out / "trajectory_online.txt", system.OnlineTrajectory());
  const auto points = system.MapPointPositions();
  WritePly(s.out / "map_points.ply", points);
  nlohmann::json semantic_json;
  if (SemanticMapper* sem = system.semantic()) {
    std::vector<Eigen::Vector3d> cloud;
    std::vector<Rgb> colours;
    std::vector<ObjectEstimate> objects;
    system.ExportSemantic(cloud, colours, objects);
    WritePly(s.out / "cloud.ply", cloud, colours);
    sem->octomap().Write(s.out / "octomap.bt");
    WriteObjectsJson(s.out / "objects.json", objects);
    WriteTopView(s.out / "map_top.png", cloud, colours, objects, trajectory);
    if (o.print_objects) PrintObjectTable(objects);
    const SemanticStats st = sem->stats();
    semantic_json = {{"keyframes", st.keyframes},
                     {"keyframes_dropped", st.dropped},
                     {"median_keyframe_ms", Median(st.ms)},
                     {"median_detect_ms", st.median_detect_ms},
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
                     {"objects", std::count_if(objects.begin(), objects.end(), [](const auto& e) { return e.exported; })}};
    if (!masks.empty()) {
      const auto truth_cloud = eval::ScoreCloud(*sem, [&](Timestamp t) { return masks.Load(t).value_or(cv::Mat()); });
      const double share = truth_cloud.points > 0 ? static_cast<double>(truth_cloud.moving) / truth_cloud.points : 0.0;
      semantic_json["truth"] = {{"keyframes", truth_cloud.keyframes},
                                {"cloud_points", truth_cloud.points},
                                {"cloud_points_on_moving_pixels", truth_cloud.moving},
                                {"moving_share", share}};
      spdlog::info("dense cloud vs ground-truth masks ({} keyframes): {:.2f} % of {} points on moving pixels",
                   truth_cloud.keyframes, 100 * share, truth_cloud.points);
      // The keyframes' depth images again, from disk: the semantic thread keeps none.
      std::unordered_map<Timestamp, std::size_t> index_of;
      for (std::size_t i = 0; i < dataset.size(); ++i) index_of[dataset.frames()[i].t_rgb] = i;
      const auto truth_map = eval::ScoreOctoMap(*sem, [&](Timestamp t) { return masks.Load(t).value_or(cv::Mat()); },
                                               [&](Timestamp t) {
                                                 const auto it = index_of.find(t);
                                                 return it == index_of.end()
                                                            ? cv::Mat()
                                                            : dataset.Load(it->second, config.camera).depth;
                                               });
      const double occupied_share =
          truth_map.path_cells > 0 ? static_cast<double>(truth_map.occupied) / truth_map.path_cells : 0.0;
      semantic_json["truth"]["octomap_path_cells"] = truth_map.path_cells;
      semantic_json["truth"]["octomap_path_cells_occupied"] = truth_map.occupied;
      semantic_json["truth"]["octomap_path_occupied_share"] = occupied_share;
      if (truth_map.path_cells > 0) {
        spdlog::info("OctoMap vs ground-truth masks: {} of {} cells on the movers' paths occupied ({:.2f} %)",
                     truth_map.occupied, truth_map.path_cells, 100 * occupied_share);
      }
    }
    if (st.dropped > 0) spdlog::warn("semantic mapping fell behind: {} keyframes left out of the map", st.dropped);
  }

  s.frames = reports.size();
  s.keyframes = system.NumKeyFrames();
  s.map_points = points.size();
  s.median_frame_ms = MedianOf(reports, &FrameReport::total_ms).get<double>();
  s.fps = seconds > 0 ? s.frames / seconds : 0.0;
  s.peak_rss_mib = PeakRssMiB();
  nlohmann::json stats = {{"dataset", dataset.dir().string()},
                          {"mode", config.dynamic.mode},
                          {"sequential", o.sequential},
                          {"realtime", o.realtime},
                          {"frames", s.frames},
                          {"tracked", s.tracked},
                          {"lost", s.lost},
                          {"keyframes", s.keyframes},
                          {"map_points", s.map_points},
                          {"median_ms", {{"extract", MedianOf(reports, &FrameReport::extract_ms)},
                                         {"detector", MedianOf(reports, &FrameReport::detector_ms)},
                                         {"detector_wait", MedianOf(reports, &FrameReport::wait_ms)},
                                         {"reject", MedianOf(reports, &FrameReport::reject_ms)},
                                         {"track", MedianOf(reports, &FrameReport::track_ms)},
                                         {"frame", s.median_frame_ms}}},
                          {"fps", s.fps},
                          {"peak_rss_mib", s.peak_rss_mib}};
  {
    std::size_t late = 0;
    double rejected = 0, features = 0;
    for (const auto& r : reports) {
      late += r.detector_late ? 1 : 0;
      rejected += r.features - r.kept;
      features += r.features;
    }
    const DetectionWorkerStats d = system.detector_stats();
    stats["dynamic"] = {{"rejected_share", features > 0 ? rejected / features : 0.0},
                        {"detector", system.DescribeDetector()},
                        {"detector_late_frames", late},
                        {"detector_submitted", d.submitted},
                        {"detector_processed", d.processed},
                        {"detector_dropped", d.dropped},
                        {"detector_errors", d.errors}};
  }
  if (truth.frames > 0) {
    stats["dynamic"]["truth"] = {{"frames", truth.frames},
                                 {"moving_keypoints", truth.moving},
                                 {"moving_rejected", truth.moving_rejected},
                                 {"recall", truth.recall()},
                                 {"static_keypoints", truth.static_points},
                                 {"static_rejected", truth.static_rejected},
                                 {"static_loss", truth.static_loss()},
                                 {"static_near_movers", truth.static_near},
                                 {"static_near_movers_rejected", truth.static_near_rejected},
                                 {"static_loss_away_from_movers", truth.static_loss_away()},
                                 {"near_movers_px", eval::MaskScore::kOutlinePx},
                                 {"precision", truth.precision()}};
    spdlog::info("dynamic rejection vs ground-truth masks ({} frames): {:.1f} % of {} moving keypoints rejected, "
                 "{:.1f} % of {} static keypoints lost ({:.1f} % of those {} px or more from a mover), precision {:.1f} %",
                 truth.frames, 100 * truth.recall(), truth.moving, 100 * truth.static_loss(), truth.static_points,
                 100 * truth.static_loss_away(), eval::MaskScore::kOutlinePx, 100 * truth.precision());
  }
  const auto mapping = system.mapping_stats();
  const auto mapping_median = [&](auto field) {
    std::vector<double> v;
    for (const auto& m : mapping) v.push_back(static_cast<double>(m.*field));
    return Median(std::move(v));
  };
  stats["local_mapping"] = {{"keyframes_processed", mapping.size()},
                            {"median_ms", mapping_median(&MappingStats::ms)},
                            {"median_insert_ms", mapping_median(&MappingStats::insert_ms)},
                            {"median_triangulate_ms", mapping_median(&MappingStats::triangulate_ms)},
                            {"median_fuse_ms", mapping_median(&MappingStats::fuse_ms)},
                            {"median_ba_ms", mapping_median(&MappingStats::ba_ms)},
                            {"median_cull_ms", mapping_median(&MappingStats::cull_ms)},
                            {"median_ba_keyframes", mapping_median(&MappingStats::local_keyframes)},
                            {"median_ba_points", mapping_median(&MappingStats::local_points)}};
  if (const auto& gba = system.final_ba(); gba && gba->local_keyframes > 0) {
    spdlog::info("final bundle adjustment: {} keyframes, {} points, {:.2f} s", gba->local_keyframes, gba->local_points,
                 gba->ms / 1000.0);
    stats["final_ba"] = {{"ms", gba->ms}, {"keyframes", gba->local_keyframes}, {"points", gba->local_points}};
  }
  if (const auto gt_path = dataset.groundtruth_path(); gt_path && trajectory.size() >= 3) {
    try {
      const auto ate = eval::ComputeAte(ReadTumTrajectory(*gt_path), trajectory, FromSeconds(0.02));
      s.ate_rmse = ate.stats.rmse;
      s.ate_pairs = ate.stats.count;
      stats["ate"] = {{"rmse", ate.stats.rmse}, {"mean", ate.stats.mean}, {"median", ate.stats.median},
                      {"pairs", ate.stats.count}};
    } catch (const Error& e) {
      spdlog::warn("no ATE: {}", e.what());
    }
  }
  if (!semantic_json.is_null()) stats["semantic"] = semantic_json;
  if (!failure.empty()) stats["error"] = failure;
  if (s.frames > 0 && s.tracked == 0) {
    spdlog::warn("no frame was tracked: the map never started, so trajectory.txt and the maps are empty");
  }
  WriteFileAtomically(s.out / "stats.json", stats.dump(2) + "\n");
  if (!failure.empty()) {
    throw InputError(failure + " (outputs of the " + std::to_string(s.frames) + " frames before it are in " +
                     s.out.string() + ")");
  }
  return s;
}

std::string FormatSummary(const RunSummary& s) {
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(1);
  o << s.frames << " frames: " << s.tracked << " tracked, " << s.lost << " lost, " << s.keyframes
    << " keyframes, " << s.map_points << " points";
  if (s.ate_rmse) {
    o.precision(4);
    o << "; ATE RMSE " << *s.ate_rmse << " m (" << s.ate_pairs << " poses)";
    o.precision(1);
  }
  o << "; median " << s.median_frame_ms << " ms/frame, " << s.fps << " fps, peak " << s.peak_rss_mib
    << " MiB. Outputs in " << s.out.string();
  return o.str();
}

}  // namespace sgslam::app
