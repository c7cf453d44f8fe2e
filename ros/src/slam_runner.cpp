#include "slam_runner.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "run_outputs.h"
#include "semantic_output.h"
#include "sgslam/camera/presets.h"
#include "sgslam/common/stats.h"
#include "sgslam/config/yaml_io.h"
#include "sgslam/detection/detector.h"
#include "sgslam/io/atomic_write.h"
#include "sgslam/io/output_plan.h"
#include "sgslam/io/ply.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/system/run_config.h"
#include "sgslam/system/slam_system.h"

namespace sgslam::ros_bridge {

namespace fs = std::filesystem;
using app::FailedOutputs;

NodeConfig LoadNodeConfig(const std::string& config, const std::string& mode, const std::string& model) {
  NodeConfig c;
  c.config.camera = *CameraPreset("tum_fr1");
  c.source = "defaults (TUM fr1 camera)";
  if (!config.empty()) {
    const fs::path file = ResolveConfigPath(config);
    LoadConfigFile(file, c.config);
    c.source = file.string() + " (over the TUM fr1 camera)";
    c.folder = file.parent_path();
    c.file = file;
  }
  if (!mode.empty()) c.config.dynamic.mode = mode;
  if (!model.empty()) c.config.detector.model_dir = model;
  if (!mode.empty() || !model.empty()) c.source += " + node parameters";
  c.config.Validate(c.source);
  return c;
}

std::unique_ptr<Detector> LoadNodeDetector(const NodeConfig& c) {
  const std::string& mode = c.config.dynamic.mode;
  return mode == "semantic" || mode == "sg" ? MakeDetector(c.config.detector, c.folder) : nullptr;
}

void CheckNodeOutputs(const NodeConfig& c, const fs::path& out) {
  OutputPlan plan;
  plan.Reads(c.file, "the configuration file given with ~config");
  app::PlanRunOutputs(plan, c.config, out, "~out", c.folder);
  plan.Check();
}

void WriteStatsWithoutFrames(const fs::path& out, const std::string& ended, const std::string& failure,
                             const LiveStats& live) {
  nlohmann::json stats = {{"source", "ros"},
                          {"topics", live.topics},
                          {"frames", 0},
                          {"live", {{"dropped", live.dropped}, {"refused", live.refused}}},
                          {"ended", failure.empty() ? ended : "failed: " + failure}};
  if (!failure.empty()) stats["error"] = failure;
  WriteFileAtomically(out / "stats.json", stats.dump(2) + "\n");
}

void WriteConfigUsed(const Config& config, const std::string& source, const fs::path& out) {
  WriteFileAtomically(out / "config_used.yaml",
                      "# effective configuration of this run (source: " + source + ")\n" + ConfigToYaml(config));
}

struct SlamRunner::Impl {
  Config config;
  fs::path out;
  bool has_detector = false;
  std::unique_ptr<SlamSystem> system;
  std::vector<FrameReport> reports;

  nlohmann::json Stats(const std::string& ended, const std::string& failure, const LiveStats& live,
                       const app::RunMaps& maps) const;
};

SlamRunner::SlamRunner(const Config& config, bool sequential, std::unique_ptr<Detector> detector, fs::path out)
    : impl_(std::make_unique<Impl>()) {
  impl_->config = config;
  impl_->out = std::move(out);
  impl_->has_detector = detector != nullptr;
  impl_->system = std::make_unique<SlamSystem>(config, sequential, std::move(detector));
  impl_->system->EnableSnapshots();
}

SlamRunner::~SlamRunner() = default;

std::shared_ptr<const FrameSnapshot> SlamRunner::Process(const RgbdImages& images) {
  FrameReport& r = impl_->reports.emplace_back(impl_->system->Process(images));
  std::vector<cv::Point2f>().swap(r.keypoints);  // the per-frame record stays small
  std::vector<std::uint8_t>().swap(r.rejected);
  return impl_->system->LatestFrame();
}

std::size_t SlamRunner::frames() const { return impl_->reports.size(); }
std::size_t SlamRunner::keyframes() const { return impl_->system->NumKeyFrames(); }
bool SlamRunner::semantic() const { return impl_->system->semantic() != nullptr; }
MapSnapshot SlamRunner::SnapshotMap() const { return impl_->system->SnapshotMap(); }
std::string SlamRunner::DescribeDetector() const { return impl_->system->DescribeDetector(); }

std::string SlamRunner::SaveNow() {
  SlamSystem& system = *impl_->system;
  const fs::path& out = impl_->out;
  FailedOutputs failed;
  failed.Try("frames.csv", [&] { app::WriteFramesCsv(out / "frames.csv", impl_->reports); });
  failed.Try("trajectory.txt", [&] { WriteTumTrajectory(out / "trajectory.txt", system.FrameTrajectory()); });
  failed.Try("keyframes.txt", [&] { WriteTumTrajectory(out / "keyframes.txt", system.KeyFrameTrajectory()); });
  failed.Try("map_points.ply", [&] { WritePly(out / "map_points.ply", system.MapPointPositions()); });
  if (SemanticMapper* sem = system.semantic()) {
    const MapSnapshot map = system.SnapshotMap();
    failed.Try("cloud.ply", [&] {
      std::vector<Eigen::Vector3d> points;
      std::vector<Rgb> colours;
      for (const CloudPiece& piece : map.cloud) {
        if (!piece.points_c) continue;
        for (const ColoredPoint& p : *piece.points_c) {
          points.push_back(piece.T_w_c * p.p.cast<double>());
          colours.push_back(p.rgb);
        }
      }
      WritePly(out / "cloud.ply", points, colours);
    });
    failed.Try("objects.json", [&] { app::WriteObjectsJson(out / "objects.json", map.objects); });
    sem->RequestOctoMap(out / "octomap.bt");
  }
  if (!failed.names.empty()) return "not written: " + failed.Joined();
  return fmt::format("written to {} ({} frames){}", out.string(), impl_->reports.size(),
                     system.semantic() ? "; octomap.bt follows after the semantic thread's current keyframe" : "");
}

bool SlamRunner::Finish(const std::string& ended, const std::string& failure, const LiveStats& live) {
  impl_->system->Finish();
  FailedOutputs failed;
  const app::RunMaps maps = app::WriteSystemOutputs(impl_->out, *impl_->system, impl_->reports, impl_->has_detector,
                                                    false, failed);
  nlohmann::json stats = impl_->Stats(failure.empty() ? ended : "failed: " + failure, failure, live, maps);
  if (!failed.names.empty()) stats["failed_outputs"] = failed.names;
  failed.Try("stats.json", [&] { WriteFileAtomically(impl_->out / "stats.json", stats.dump(2) + "\n"); });
  return failed.names.empty();
}

nlohmann::json SlamRunner::Impl::Stats(const std::string& ended, const std::string& failure, const LiveStats& live,
                                       const app::RunMaps& maps) const {
  std::size_t tracked = 0, lost = 0;
  for (const FrameReport& r : reports) tracked += r.state == TrackState::kOk, lost += r.state == TrackState::kLost;
  nlohmann::json stats = {{"source", "ros"},
                          {"topics", live.topics},
                          {"mode", config.dynamic.mode},
                          {"frames", reports.size()},
                          {"tracked", tracked},
                          {"lost", lost},
                          {"keyframes", system->NumKeyFrames()},
                          {"map_points", maps.map_points},
                          {"median_ms", app::MedianMsJson(reports, app::MedianFrameMs(reports))},
                          {"peak_rss_mib", PeakRssMiB()},
                          {"dynamic", app::DynamicJson(reports, *system)},
                          {"local_mapping", app::LocalMappingJson(*system)},
                          {"loop", app::LoopJson(reports, *system)},
                          {"live", app::LiveJson(live.dropped, live.latency_ms)},
                          {"ended", ended}};
  stats["live"]["refused"] = live.refused;
  if (!maps.semantic.is_null()) stats["semantic"] = maps.semantic;
  if (!failure.empty()) stats["error"] = failure;
  return stats;
}

}  // namespace sgslam::ros_bridge
