#include "run_pipeline.h"

#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <exception>
#include <csignal>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <set>
#include <sstream>
#include <utility>

#include "mcap_recorder.h"
#include "progress.h"
#include "run_foxglove.h"
#include "run_outputs.h"
#include "run_viewer.h"
#include "stop_signals.h"
#include "sgslam/common/error.h"
#include "sgslam/common/stats.h"
#include "sgslam/detection/detector.h"
#include "sgslam/detection/people_scale.h"
#include "sgslam/eval/ate.h"
#include "sgslam/eval/evaluate.h"
#include "sgslam/eval/object_score.h"
#include "sgslam/eval/track_score.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/io/output_plan.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/mapfile/map_file.h"
#include "sgslam/system/run_config.h"
#include "sgslam/system/slam_system.h"
#include "truth_scorer.h"

namespace sgslam::app {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kPrefetchFrames = 3;  // frames the reader decodes ahead of tracking

std::atomic<bool> g_octomap_requested{false};
extern "C" void OnOctoMapRequest(int) { g_octomap_requested = true; }

// The run's signals (stop_signals.h), and SIGUSR1 (`kill -USR1 <pid>`), which asks
// for the OctoMap built so far, in octomap_live.bt (run_outputs.h), and for the map
// in the --save-map file; the previous handler comes back on scope exit.
class InterruptGuard {
 public:
  InterruptGuard() : previous_usr1_(std::signal(SIGUSR1, OnOctoMapRequest)) { g_octomap_requested = false; }
  ~InterruptGuard() { std::signal(SIGUSR1, previous_usr1_); }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  StopSignals stop_;
  void (*previous_usr1_)(int);
};

// The file's configuration (run_config.h) with the command line's options on top,
// validated again when they changed it.
RunConfig Configure(const RunOptions& o) {
  RunConfig rc = ResolveRunConfig(o.config.empty() ? std::nullopt : std::optional<fs::path>(o.config), o.dataset);
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
  return rc;
}

// Every path the run writes checked against those it reads (io/output_plan.h),
// before anything is written; then the output folder made.
fs::path MakeOutputFolder(const RunOptions& o, const RunConfig& rc, const TumDataset& dataset) {
  const fs::path out = o.out.empty() ? fs::path("sgslam-out") / dataset.name() : fs::path(o.out);
  OutputPlan plan;
  plan.ReadsFolder(dataset.dir(), "the dataset folder");
  std::set<fs::path> image_folders;
  for (const FrameRecord& f : dataset.frames()) image_folders.insert({f.rgb.parent_path(), f.depth.parent_path()});
  for (const fs::path& folder : image_folders) plan.ReadsFolder(folder, "a folder of the dataset's images");
  if (!o.config.empty()) plan.Reads(ResolveConfigPath(o.config), "the configuration file given with --config");
  PlanRunOutputs(plan, rc.config, out, "--out", dataset.dir());
  std::error_code ec;
  const bool map_in_place = !o.load_map.empty() && !o.save_map.empty() && fs::equivalent(o.load_map, o.save_map, ec);
  if (!map_in_place) plan.Reads(o.load_map, "the map given with --load-map");  // saved over on purpose, else kept
  if (!o.save_map.empty()) plan.Writes(o.save_map, "--save-map", std::string(mapfile::kFileMagic));
  if (!o.mcap.empty()) {
    plan.Writes(o.mcap, "--mcap", std::string(mcap::kFileMagic));
    plan.Writes(o.mcap + ".part", "--mcap's file while it is written", std::string(mcap::kFileMagic));
  }
  plan.Check();
  fs::create_directories(out, ec);
  if (ec || !fs::is_directory(out)) throw InputError("cannot create output folder " + out.string());
  for (const auto& [option, file] : {std::pair{"--save-map", o.save_map}, {"--mcap", o.mcap}}) {
    if (file.empty()) continue;
    const fs::path dir = fs::path(file).has_parent_path() ? fs::path(file).parent_path() : fs::path(".");
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir, ec)) throw InputError(std::string(option) + " " + file + ": cannot create folder " + dir.string());
  }
  return out;
}

// Loaded before any thread starts, so a missing or broken model is reported at
// once; only the modes that use boxes need one.
std::unique_ptr<Detector> LoadDetector(const Config& config, const fs::path& dataset_dir) {
  const bool uses_boxes = config.dynamic.mode == "semantic" || config.dynamic.mode == "sg";
  return uses_boxes ? MakeDetector(config.detector, dataset_dir) : nullptr;
}

struct FrameLoop {
  std::vector<FrameReport> reports;
  std::string failure;  // the error that ended the loop early, after some frames
  int stopped_by = 0;   // the signal that ended it early
  PeopleScaleCheck people;  // the depth scale by the size of detected people
  // --realtime: frames replaced in the one-slot buffer while the system was busy,
  // and per frame processed, ms from its arrival (its timestamp's time) to its pose.
  std::size_t dropped = 0;
  std::vector<double> latency_ms;
};

// The frames to process, from the stream. With --realtime a frame arrives at the
// time of its timestamp (counted from the first frame's) and is waited for; then,
// unless --every-frame, the frames that have arrived meanwhile replace one another
// in a one-slot buffer and the newest is taken, the others counted as dropped. To
// know whether a newer frame has arrived the stream is read one frame ahead; a
// frame that cannot be read is reported when its turn comes, so that the frames
// before it are all processed.
class FrameSource {
 public:
  FrameSource(const RunOptions& o, FrameStream& stream) : o_(o), stream_(stream) {}

  std::optional<RgbdImages> Take() {
    std::optional<RgbdImages> frame = Read();
    if (!frame || !o_.realtime) return frame;
    arrival_ = Arrival(*frame);
    StopSignals::WaitUntil(arrival_);  // cut short by a stop signal: an hour's gap must not hold a SIGTERM
    while (!o_.every_frame && !error_) {
      try {
        ahead_ = stream_.Next();
      } catch (...) {
        error_ = std::current_exception();  // rethrown by the next Take
        break;
      }
      if (!ahead_ || Arrival(*ahead_) > std::chrono::steady_clock::now()) break;
      ++dropped_;
      frame = std::move(ahead_);
      ahead_.reset();
      arrival_ = Arrival(*frame);
    }
    return frame;
  }

  // When the frame last taken arrived (--realtime).
  std::chrono::steady_clock::time_point arrival() const { return arrival_; }
  std::size_t dropped() const { return dropped_; }

 private:
  std::optional<RgbdImages> Read() {
    if (ahead_) {
      std::optional<RgbdImages> f = std::move(ahead_);
      ahead_.reset();
      return f;
    }
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
    return stream_.Next();
  }

  std::chrono::steady_clock::time_point Arrival(const RgbdImages& frame) {
    if (!started_) started_ = true, t_first_ = frame.t, start_ = std::chrono::steady_clock::now();
    return start_ + std::chrono::nanoseconds(frame.t - t_first_);
  }

  const RunOptions& o_;
  FrameStream& stream_;
  std::optional<RgbdImages> ahead_;
  std::exception_ptr error_;
  std::size_t dropped_ = 0;
  bool started_ = false;
  Timestamp t_first_ = 0;
  std::chrono::steady_clock::time_point start_, arrival_;
};

// Streams the dataset through the system: the frames at their timestamps' pace
// with o.realtime, the progress bar, the truth scores, Ctrl-C and SIGUSR1.
FrameLoop RunFrames(const RunOptions& o, const TumDataset& dataset, const Config& config, SlamSystem& system,
                    TruthScorer& truth, const fs::path& out, const Stopwatch& wall, RunViewer* viewer,
                    McapRecorder* recorder, RunFoxglove* foxglove) {
  FrameLoop loop;
  FrameStream stream(dataset, config.camera, kPrefetchFrames, o.max_frames);
  ProgressBar progress(stream.size());
  FrameSource source(o, stream);
  try {
    while (auto frame = source.Take()) {
      if (loop.reports.empty()) {
        if (const auto warning = CheckDepthScale(*frame, dataset.frames()[frame->index], config.camera, config.dataset)) {
          spdlog::warn("{}", *warning);
        }
      }
      FrameReport& r = loop.reports.emplace_back(system.Process(*frame));
      if (recorder) recorder->AddFrame();
      if (foxglove) foxglove->AddFrame();
      if (o.realtime) {
        loop.latency_ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - source.arrival()).count());
      }
      if (const auto warning = loop.people.Add(frame->depth, r.boxes, config.camera)) spdlog::warn("{}", *warning);
      truth.AddFrame(r);
      if (viewer) viewer->AddFrame(r);
      // Keep the per-frame record small: swapped out, as `= {}` keeps the capacity.
      std::vector<cv::Point2f>().swap(r.keypoints);
      std::vector<std::uint8_t>().swap(r.rejected);
      progress.Update(loop.reports.size(), loop.reports.size() / (wall.ElapsedMs() * 1e-3));
      if (g_octomap_requested.exchange(false)) {
        if (SemanticMapper* sem = system.semantic()) {
          RequestLiveOctoMap(out, *sem);
        } else if (o.save_map.empty()) {
          spdlog::warn("OctoMap requested (SIGUSR1), but the semantic thread is off (semantic.enabled)");
        }
        if (!o.save_map.empty()) system.SaveMap(o.save_map);
      }
      if (viewer) viewer->WaitWhilePaused();
      if ((loop.stopped_by = StopSignals::Received()) != 0) {
        spdlog::warn("interrupted by {}: writing the outputs of the {} frames processed", SignalName(loop.stopped_by),
                     loop.reports.size());
        break;
      }
    }
  } catch (const Error& e) {
    if (loop.reports.empty()) throw;
    loop.failure = e.what();  // save what was done, then report
  } catch (const std::exception& e) {  // a library's own (OpenCV refusing an image, say)
    if (loop.reports.empty()) throw;
    loop.failure = std::string("unexpected failure: ") + e.what();
  }
  loop.dropped = source.dropped();
  if (loop.dropped > 0) {
    spdlog::info("--realtime: {} frames dropped (arrived while the system was busy)", loop.dropped);
  }
  return loop;
}

// The ATE against the folder's groundtruth.txt, when it has one (and the run 3
// poses); none, warned, when it cannot be computed.
std::optional<eval::AteResult> RunAte(const TumDataset& dataset, const Trajectory& trajectory) {
  const auto gt_path = dataset.groundtruth_path();
  if (!gt_path || trajectory.size() < 3) return std::nullopt;
  try {
    return eval::ComputeAte(ReadTumTrajectory(*gt_path), trajectory, FromSeconds(0.02));
  } catch (const Error& e) {
    spdlog::warn("no ATE: {}", e.what());
    return std::nullopt;
  }
}

// The ATE into s and stats.
void AddAte(const std::optional<eval::AteResult>& ate, RunSummary& s, nlohmann::json& stats) {
  if (!ate) return;
  s.ate_rmse = ate->stats.rmse;
  s.ate_pairs = ate->stats.count;
  stats["ate"] = {{"rmse", ate->stats.rmse}, {"mean", ate->stats.mean}, {"median", ate->stats.median},
                  {"pairs", ate->stats.count}};
}

// The mover tracks against the sequence's true movers (eval/track_score.h), into
// tracks["truth"], when it has them and ground truth; a truth that cannot be read
// costs the scores (warned), not stats.json.
void AddTrackTruth(const TumDataset& dataset, const CameraConfig& camera, const SlamSystem& system,
                   const Trajectory& trajectory, nlohmann::json& tracks) {
  const auto gt_path = dataset.groundtruth_path();
  if (!gt_path || trajectory.size() < 3) return;
  try {
    const std::optional<eval::MoverTruth> truth = eval::LoadMoverTruth(dataset.dir(), camera);
    if (!truth) return;
    const eval::TrackScoreOptions options;
    const eval::TrackScore score =
        eval::ScoreTracks(*truth, system.MoverTracks(), trajectory, ReadTumTrajectory(*gt_path), options);
    tracks["truth"] = eval::ToJson(score, options);
  } catch (const std::exception& e) {
    spdlog::warn("no scores of the mover tracks against the true movers: {}", e.what());
  }
}

// stats.json (but its semantic section and how the run ended: WriteStatsJson), and
// the summary's counts into s.
nlohmann::json RunStats(const RunOptions& o, const Config& config, const TumDataset& dataset, const FrameLoop& loop,
                        const SlamSystem& system, const RunMaps& maps, const TruthScorer& truth,
                        const std::optional<eval::AteResult>& ate, double seconds, RunSummary& s) {
  const RunTotals totals = TotalsOf(loop.reports, system, maps.map_points);
  s.frames = totals.frames;
  s.tracked = totals.tracked;
  s.odometry = totals.odometry;
  s.lost = totals.lost;
  s.keyframes = totals.keyframes;
  s.map_points = totals.map_points;
  s.median_frame_ms = totals.median_frame_ms;
  s.peak_rss_mib = totals.peak_rss_mib;
  s.fps = seconds > 0 ? s.frames / seconds : 0.0;
  nlohmann::json stats = SystemStatsJson(config, totals, loop.reports, system);
  stats["dataset"] = dataset.dir().string();
  stats["sequential"] = o.sequential;
  stats["realtime"] = o.realtime;
  stats["fps"] = s.fps;
  if (nlohmann::json t = truth.RejectionJson(); !t.is_null()) stats["dynamic"]["truth"] = t;
  const Trajectory& trajectory = maps.trajectory;
  AddAte(ate, s, stats);
  if (o.realtime) {
    stats["live"] = LiveJson(loop.dropped, loop.latency_ms);
    stats["live"]["every_frame"] = o.every_frame;
  }
  if (stats.contains("tracks")) AddTrackTruth(dataset, config.camera, system, trajectory, stats["tracks"]);
  if (const auto h = loop.people.median_height()) {
    stats["dynamic"]["people_measured"] = loop.people.measured();
    stats["dynamic"]["people_median_height_m"] = *h;
    stats["dynamic"]["people_tallest_m"] = *loop.people.tallest();
  }
  if (!o.load_map.empty() || !o.save_map.empty()) {
    stats["map_file"] = {{"loaded", o.load_map}, {"localize", o.localize}, {"saved", o.save_map},
                         {"saves", system.maps_saved()}};
  }
  return stats;
}

// The semantic scores against ground-truth masks, into semantic["truth"]. Scoring
// rereads masks and depth; one that cannot be read costs the scores (warned), not
// stats.json.
void AddSemanticTruth(const TruthScorer& truth, const SemanticMapper& sem, const TumDataset& dataset,
                      const CameraConfig& camera, nlohmann::json& semantic) {
  try {
    if (nlohmann::json t = truth.SemanticJson(sem, dataset, camera); !t.is_null()) semantic["truth"] = t;
  } catch (const std::exception& e) {
    spdlog::warn("no scores of the semantic map against the ground-truth masks: {}", e.what());
  }
}

// The object map against the sequence's true objects (--object-truth, or the
// dataset's objects_gt.json), in the ground truth's world by the run's ATE
// alignment, into semantic["objects_truth"]; a list that cannot be read costs the
// scores (warned), not stats.json. An --object-truth the run cannot score (no ATE)
// is said.
void AddObjectTruth(const RunOptions& o, const TumDataset& dataset, const SlamSystem& system,
                    const std::optional<eval::AteResult>& ate, nlohmann::json& semantic) {
  fs::path list = o.object_truth;
  if (list.empty() && fs::is_regular_file(dataset.dir() / "objects_gt.json")) list = dataset.dir() / "objects_gt.json";
  if (list.empty()) return;
  if (!ate) {
    spdlog::warn("--object-truth {}: not scored, the run has no ATE alignment (ground truth and 3 poses)",
                 list.string());
    return;
  }
  try {
    const auto truth = eval::LoadObjectTruth(list);
    std::vector<ObjectEstimate> objects = system.ExportObjects(ate->T_gt_est);
    std::erase_if(objects, [](const ObjectEstimate& e) { return !e.exported; });
    semantic["objects_truth"] = eval::ToJson(eval::ScoreObjects(truth, objects));
    semantic["objects_truth"]["list"] = list.string();
  } catch (const std::exception& e) {
    spdlog::warn("no scores of the object map against {}: {}", list.string(), e.what());
  }
}

// Every output but stats.json, each on its own (run_outputs.h), and the semantic
// map's scores against the dataset's ground-truth masks.
RunMaps WriteOutputs(const RunOptions& o, const Config& config, const TumDataset& dataset, FrameLoop& loop,
                     SlamSystem& system, const TruthScorer& truth, bool has_detector, const fs::path& out,
                     FailedOutputs& failed) {
  RunMaps maps = WriteSystemOutputs(out, system, loop.reports, has_detector, o.print_objects, failed);
  if (const SemanticMapper* sem = system.semantic()) AddSemanticTruth(truth, *sem, dataset, config.camera, maps.semantic);
  return maps;
}

// --load-map loaded, before the first frame.
void StartFromMap(const RunOptions& o, SlamSystem& system) {
  if (o.load_map.empty()) return;
  const Stopwatch load;
  system.LoadMap(mapfile::ReadMapFile(o.load_map), o.load_map);
  system.SetLocalizationOnly(o.localize);
  spdlog::info("map loaded in {:.0f} ms (read, checked and restored)", load.ElapsedMs());
}

// The --save-map file after Finish(); false when it should have been written and was
// not (an empty map is not saved, and that is no failure).
bool SaveMapAtEnd(const RunOptions& o, SlamSystem& system) {
  if (o.save_map.empty()) return true;
  const std::size_t before = system.maps_saved();
  system.SaveMap(o.save_map);
  return system.maps_saved() > before || system.NumKeyFrames() == 0;
}

}  // namespace

RunSummary RunSequence(const RunOptions& o) {
  // For the whole run: a SIGUSR1 before the first frame or while the outputs are
  // written must not end the process (the default action) and lose them.
  const InterruptGuard guard;
  const RunConfig rc = Configure(o);
  const Config& config = rc.config;
  TumDataset dataset(o.dataset, config.dataset);
  RunSummary s;
  s.out = MakeOutputFolder(o, rc, dataset);
  spdlog::info("dataset {}: {} RGB-D frames ({}), config: {}", dataset.dir().string(), dataset.size(),
               dataset.associations_from_file() ? "associations.txt" : "associated by timestamp", rc.source);
  WriteConfigUsed(s.out, rc.config, rc.source);

  // Process-wide, before any thread starts: OpenCV's own worker threads (resize,
  // blur, LK, inference) would compete with local mapping and the detector for the
  // two cores (detection/dnn_detector.h).
  if (config.detector.threads > 0) cv::setNumThreads(config.detector.threads);
  std::unique_ptr<Detector> detector = LoadDetector(config, o.dataset);
  const bool has_detector = detector != nullptr;
  SlamSystem system(config, o.sequential, std::move(detector));
  spdlog::info("mode {}, detector: {}", config.dynamic.mode, system.DescribeDetector());
  StartFromMap(o, system);
  if (config.camera.readout > 0) {
    spdlog::info("rolling shutter: rows read out over {:.0f} ms (camera.readout; 0 for a global shutter)",
                 1000 * config.camera.readout);
  }
  std::unique_ptr<RunViewer> viewer;  // before the system goes, it stops
  if (o.viewer_port >= 0) {
    const std::size_t frames = o.max_frames > 0 ? std::min(o.max_frames, dataset.size()) : dataset.size();
    Trajectory truth;  // drawn aligned to the keyframes
    if (const auto gt = dataset.groundtruth_path()) {
      try {
        truth = eval::UniqueStamps(ReadTumTrajectory(*gt));
      } catch (const Error& e) {
        spdlog::warn("viewer: no ground truth shown: {}", e.what());
      }
    }
    viewer = std::make_unique<RunViewer>(system, o.viewer_address, o.viewer_port,
                                         nlohmann::json{{"live", true},
                                                        {"dataset", dataset.dir().filename().string()},
                                                        {"mode", config.dynamic.mode},
                                                        {"frames", frames},
                                                        {"pausable", true}},
                                         std::move(truth), o.viewer_origins);
  }
  std::unique_ptr<RunFoxglove> foxglove;  // likewise
  if (o.foxglove_port >= 0) {
    foxglove = std::make_unique<RunFoxglove>(system, o.foxglove_address, o.foxglove_port, config.camera);
  }
  std::unique_ptr<McapRecorder> recorder;  // likewise; last, when nothing else can fail before the frames
  if (!o.mcap.empty()) recorder = std::make_unique<McapRecorder>(o.mcap, system, config.camera, o.realtime);
  TruthScorer truth(o.dataset);
  const Stopwatch wall;
  FrameLoop loop =
      RunFrames(o, dataset, config, system, truth, s.out, wall, viewer.get(), recorder.get(), foxglove.get());
  system.Finish();
  if (foxglove) foxglove->Finish();
  const double seconds = wall.ElapsedMs() * 1e-3;
  const bool map_saved = SaveMapAtEnd(o, system);  // before the export filters the semantic clouds

  FailedOutputs failed;
  if (recorder) {
    failed.Try("--mcap " + o.mcap, [&] {
      if (const std::string error = recorder->Finish(); !error.empty()) throw InputError(error);
    });
  }
  RunMaps maps = WriteOutputs(o, config, dataset, loop, system, truth, has_detector, s.out, failed);
  const std::optional<eval::AteResult> ate = RunAte(dataset, maps.trajectory);
  if (system.semantic()) AddObjectTruth(o, dataset, system, ate, maps.semantic);
  const nlohmann::json stats = RunStats(o, config, dataset, loop, system, maps, truth, ate, seconds, s);
  s.stopped_by = loop.stopped_by;
  if (s.frames > 0 && s.tracked == 0) {
    spdlog::warn("no frame was tracked: the map never started, so trajectory.txt and the maps are empty");
  }
  WriteStatsJson(s.out, stats, maps.semantic,
                 loop.stopped_by ? std::string("interrupted by ") + SignalName(loop.stopped_by) : "completed",
                 loop.failure, failed);
  if (!failed.names.empty()) {
    throw InputError("outputs not written: " + failed.Joined() + " (the others are in " + s.out.string() + ")");
  }
  if (!map_saved) {
    throw InputError("the map was not saved to " + o.save_map + " (see the error above); the other outputs are in " +
                     s.out.string());
  }
  if (!loop.failure.empty()) {
    throw InputError(loop.failure + " (outputs of the " + std::to_string(s.frames) + " frames before it are in " +
                     s.out.string() + ")");
  }
  return s;
}

std::string FormatSummary(const RunSummary& s) {
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(1);
  o << s.frames << " frames: " << s.tracked << " tracked, ";
  if (s.odometry > 0) o << s.odometry << " by odometry, ";
  o << s.lost << " lost, " << s.keyframes
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
