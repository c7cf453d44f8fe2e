// sgslam run: process an RGB-D sequence and write the outputs of the contract in
// architecture.md. Tracking arrives with the SLAM core; until then this command
// checks and streams every frame and says plainly that no trajectory is produced.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "commands.h"
#include "progress.h"
#include "sgslam/common/error.h"
#include "sgslam/common/stats.h"
#include "sgslam/config/yaml_io.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/io/text_file.h"
#include "sgslam/io/tum_dataset.h"
#include "sgslam/system/run_config.h"

namespace sgslam::app {

namespace fs = std::filesystem;

namespace {

struct RunOptions {
  std::string dataset, config, out, mode = "sg", model;
  bool no_detector = false, sequential = false;
  std::size_t max_frames = 0;
  int viewer_port = 0;
};

int Run(const RunOptions& o) {
  const fs::path dataset_dir = o.dataset;
  RunConfig rc = ResolveRunConfig(o.config.empty() ? std::nullopt : std::optional<fs::path>(o.config), dataset_dir);
  const Config& config = rc.config;
  TumDataset dataset(dataset_dir, config.dataset);
  const fs::path out = o.out.empty() ? fs::path("sgslam-out") / dataset.name() : fs::path(o.out);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec || !fs::is_directory(out)) throw InputError("cannot create output folder " + out.string() + ": " + ec.message());

  spdlog::info("dataset {}: {} RGB-D frames ({}), config: {}", dataset.dir().string(), dataset.size(),
               dataset.associations_from_file() ? "associations.txt" : "associated by timestamp", rc.source);
  const std::string yaml = "# effective configuration of this run (source: " + rc.source + ")\n" + ConfigToYaml(config);
  spdlog::debug("effective configuration:\n{}", yaml);
  WriteFileAtomically(out / "config_used.yaml", yaml);
  if (o.mode != "none" && !o.no_detector) {
    spdlog::warn("--mode {}: dynamic rejection and detection are not built yet; frames are only read", o.mode);
  }
  if (o.viewer_port != 0) spdlog::warn("--viewer is not built yet; ignored");

  FrameStream stream(dataset, config.camera, static_cast<std::size_t>(config.dataset.prefetch), o.max_frames);
  ProgressBar progress(stream.size());
  std::ostringstream csv;
  csv << "index,timestamp,state,read_ms\n";
  std::vector<double> read_ms;
  Stopwatch total, wait;
  std::size_t frames = 0;
  while (auto frame = stream.Next()) {
    read_ms.push_back(wait.ElapsedMs());
    if (frames == 0) CheckDepthScale(*frame, dataset.frames()[frame->index], config.camera, config.dataset);
    csv << frame->index << "," << FormatTimestamp(frame->t) << ",not_tracked," << read_ms.back() << "\n";
    ++frames;
    progress.Update(frames, frames / (total.ElapsedMs() * 1e-3));
    wait.Restart();
  }
  const double seconds = total.ElapsedMs() * 1e-3;
  WriteFileAtomically(out / "frames.csv", csv.str());
  nlohmann::json stats = {{"dataset", dataset.dir().string()},
                          {"frames", frames},
                          {"tracked", 0},
                          {"lost", 0},
                          {"tracking", "not implemented yet"},
                          {"median_read_ms", Median(read_ms)},
                          {"fps", seconds > 0 ? frames / seconds : 0.0},
                          {"peak_rss_mib", PeakRssMiB()}};
  WriteFileAtomically(out / "stats.json", stats.dump(2) + "\n");
  std::printf("%zu frames read and checked in %.1f s (%.0f fps), peak memory %.0f MiB. Tracking is not "
              "implemented yet: no trajectory.txt was written. Outputs in %s\n",
              frames, seconds, seconds > 0 ? frames / seconds : 0.0, PeakRssMiB(), out.string().c_str());
  return kExitOk;
}

}  // namespace

Action AddRunCommand(CLI::App& root) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = root.add_subcommand("run", "Run SLAM on an RGB-D sequence in the TUM layout");
  cmd->add_option("--dataset", o->dataset, "Dataset folder (rgb.txt, depth.txt[, associations.txt, groundtruth.txt])")
      ->required();
  cmd->add_option("--config", o->config, "YAML config (default: the dataset's sgslam.yaml or a preset by folder name)");
  cmd->add_option("--out", o->out, "Output folder (default: ./sgslam-out/<dataset name>)");
  cmd->add_option("--mode", o->mode, "Dynamic feature rejection: none, semantic, geometric or sg")
      ->check(CLI::IsMember({"none", "semantic", "geometric", "sg"}));
  cmd->add_option("--model", o->model, "Detector model folder (or $SGSLAM_MODEL_DIR)");
  cmd->add_flag("--no-detector", o->no_detector, "Run without the object detector (geometry only)");
  cmd->add_option("--max-frames", o->max_frames, "Stop after N frames (0: all)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--sequential", o->sequential, "Step every module in one thread (deterministic)");
  cmd->add_option("--viewer", o->viewer_port, "Serve the live viewer on PORT")->expected(0, 1)->default_str("8080");
  return [o] { return Run(*o); };
}

}  // namespace sgslam::app
