#include "slam_runner.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>
#include <opencv2/core/utility.hpp>

#include "mcap_recorder.h"
#include "run_outputs.h"
#include "sgslam/camera/presets.h"
#include "sgslam/common/error.h"
#include "sgslam/config/yaml_io.h"
#include "sgslam/detection/detector.h"
#include "sgslam/io/output_plan.h"
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

void CheckNodeOutputs(const NodeConfig& c, const fs::path& out, const std::string& mcap) {
  OutputPlan plan;
  plan.Reads(c.file, "the configuration file given with ~config");
  app::PlanRunOutputs(plan, c.config, out, "~out", c.folder);
  if (!mcap.empty()) {
    plan.Writes(mcap, "~mcap", std::string(mcap::kFileMagic));
    plan.Writes(mcap + ".part", "~mcap's file while it is written", std::string(mcap::kFileMagic));
  }
  plan.Check();
  if (mcap.empty()) return;
  for (const app::foxglove::ChannelInfo& channel : app::foxglove::Channels()) app::foxglove::SchemaText(channel.schema);
  const fs::path dir = fs::path(mcap).has_parent_path() ? fs::path(mcap).parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir, ec)) throw InputError("~mcap " + mcap + ": cannot create folder " + dir.string());
}

bool WriteStatsWithoutFrames(const fs::path& out, const std::string& ended, const std::string& failure,
                             const LiveStats& live) {
  const nlohmann::json stats = {{"source", "ros"},
                                {"topics", live.topics},
                                {"frames", 0},
                                {"live", {{"dropped", live.dropped}, {"refused", live.refused}}}};
  FailedOutputs failed;
  app::WriteStatsJson(out, stats, nullptr, ended, failure, failed);
  return failed.names.empty();
}

void WriteConfigUsed(const Config& config, const std::string& source, const fs::path& out) {
  app::WriteConfigUsed(out, config, source);
}

struct SlamRunner::Impl {
  Config config;
  fs::path out;
  bool has_detector = false;
  std::unique_ptr<SlamSystem> system;
  std::unique_ptr<app::McapRecorder> recorder;  // after the system: gone before it
  std::string mcap, mcap_error;  // the file, and why it could not be opened
  std::vector<FrameReport> reports;

  nlohmann::json Stats(const LiveStats& live, const app::RunMaps& maps) const;
};

SlamRunner::SlamRunner(const Config& config, bool sequential, std::unique_ptr<Detector> detector, fs::path out,
                       const std::string& mcap)
    : impl_(std::make_unique<Impl>()) {
  impl_->config = config;
  impl_->out = std::move(out);
  impl_->has_detector = detector != nullptr;
  // Process-wide, as `sgslam run` does (detection/dnn_detector.h): the node has
  // nothing else of OpenCV's running yet.
  if (config.detector.threads > 0) cv::setNumThreads(config.detector.threads);
  impl_->system = std::make_unique<SlamSystem>(config, sequential, std::move(detector));
  impl_->system->EnableSnapshots();
  impl_->mcap = mcap;
  if (mcap.empty()) return;
  try {  // live: a recording that falls behind drops frames, tracking never waits for it
    impl_->recorder = std::make_unique<app::McapRecorder>(mcap, *impl_->system, config.camera, true);
  } catch (const std::exception& e) {  // the run goes on without it, and ends naming it
    impl_->mcap_error = e.what();
    spdlog::error("~mcap: {}; the run goes on without a recording", impl_->mcap_error);
  }
}

SlamRunner::~SlamRunner() = default;

std::shared_ptr<const FrameSnapshot> SlamRunner::Process(const RgbdImages& images) {
  FrameReport& r = impl_->reports.emplace_back(impl_->system->Process(images));
  if (impl_->recorder) impl_->recorder->AddFrame();
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
  FailedOutputs failed;
  app::WriteLiveOutputs(impl_->out, *impl_->system, impl_->reports, failed);
  if (!failed.names.empty()) return "not written: " + failed.Joined();
  return fmt::format("written to {} ({} frames){}", impl_->out.string(), impl_->reports.size(),
                     semantic() ? "; octomap_live.bt follows after the semantic thread's current keyframe" : "");
}

bool SlamRunner::Finish(const std::string& ended, const std::string& failure, const LiveStats& live) {
  impl_->system->Finish();
  FailedOutputs failed;
  if (impl_->recorder || !impl_->mcap_error.empty()) {
    failed.Try("~mcap " + impl_->mcap, [&] {
      const std::string error = impl_->recorder ? impl_->recorder->Finish() : impl_->mcap_error;
      if (!error.empty()) throw InputError(error);
    });
  }
  const app::RunMaps maps = app::WriteSystemOutputs(impl_->out, *impl_->system, impl_->reports, impl_->has_detector,
                                                    false, failed);
  app::WriteStatsJson(impl_->out, impl_->Stats(live, maps), maps.semantic, ended, failure, failed);
  return failed.names.empty();
}

// stats.json's sections of `sgslam run` (run_outputs.h), the topics and the live
// section with the frames refused as bad input.
nlohmann::json SlamRunner::Impl::Stats(const LiveStats& live, const app::RunMaps& maps) const {
  nlohmann::json stats =
      app::SystemStatsJson(config, app::TotalsOf(reports, *system, maps.map_points), reports, *system);
  stats["source"] = "ros";
  stats["topics"] = live.topics;
  stats["live"] = app::LiveJson(live.dropped, live.latency_ms);
  stats["live"]["refused"] = live.refused;
  return stats;
}

}  // namespace sgslam::ros_bridge
