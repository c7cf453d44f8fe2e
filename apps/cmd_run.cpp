// sgslam run: process an RGB-D sequence and write the outputs of the contract in
// docs/architecture.md, "Outputs" (see run_pipeline.h).
#include <CLI/CLI.hpp>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "port_option.h"
#include "run_pipeline.h"
#include "run_foxglove.h"
#include "run_viewer.h"

namespace sgslam::app {

namespace {

// CLI11 2.1 converts a count past 2^64 - 1 to 2^64 - 1 (strtoull's range error
// unchecked): such a count is refused as a bad command line instead.
const CLI::Validator kCount64(
    [](std::string& text) {
      std::uint64_t value = 0;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (ec == std::errc::result_out_of_range) return "Value " + text + " is out of range (at most 2^64 - 1)";
      return std::string();
    },
    "", "64-bit count");

}  // namespace

Action AddRunCommand(CLI::App& root) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = root.add_subcommand("run", "Run SLAM on an RGB-D sequence in the TUM layout");
  cmd->add_option("--dataset", o->dataset, "Dataset folder (rgb.txt, depth.txt[, associations.txt, groundtruth.txt])")
      ->required();
  cmd->add_option("--config", o->config, "YAML config file, or the name of one shipped with sgslam (tum_fr1, tum_fr2, tum_fr3, bonn); default: the dataset's sgslam.yaml or a preset by folder name");
  cmd->add_option("--out", o->out, "Output folder (default: ./sgslam-out/<dataset name>)");
  cmd->add_option("--mode", o->mode, "Dynamic feature rejection: none, semantic, geometric or sg")
      ->check(CLI::IsMember({"none", "semantic", "geometric", "sg"}));
  cmd->add_option("--model", o->model, "Detector model folder (default: $SGSLAM_MODEL_DIR, else the models shipped with sgslam)");
  cmd->add_flag("--no-detector", o->no_detector, "Run without the object detector (geometry only)");
  cmd->add_option("--max-frames", o->max_frames, "Stop after N frames (0: all)")->check(CLI::NonNegativeNumber)->check(kCount64);
  cmd->add_flag("--sequential", o->sequential, "Step every module in one thread (deterministic output)");
  CLI::Option* realtime = cmd->add_flag("--realtime", o->realtime,
                "Hand frames over at the pace of their timestamps, like a live camera (default: as fast as they load); "
                "a frame that arrives while the system is busy is replaced by the next one (dropped)");
  cmd->add_flag("--every-frame", o->every_frame,
                "With --realtime: process every frame, late or not (none dropped; the delay may grow)")
      ->needs(realtime);
  CLI::Option* load = cmd->add_option("--load-map", o->load_map, "Start from the map saved in FILE (--save-map) and extend it")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--localize", o->localize,
                "With --load-map: track in the map without adding keyframes or points (dynamic rejection stays on)")
      ->needs(load);
  cmd->add_option("--save-map", o->save_map, "Save the whole map to FILE at the end (and on SIGUSR1 during the run)");
  cmd->add_option("--object-truth", o->object_truth,
                  "Score the object map against this list of the sequence's true objects (stats.json's "
                  "semantic.objects_truth; docs/object-map.md); default: the dataset's objects_gt.json, if any")
      ->check(CLI::ExistingFile);
  cmd->add_option("--mcap", o->mcap,
                  "Record the run to FILE as MCAP for Foxglove: camera pose, image with keypoints and boxes, "
                  "trajectory, map, dense cloud, objects, mover tracks (docs/foxglove.md)");
  const PortOption foxglove(*cmd, "--foxglove", kDefaultFoxglovePort,
                            "Serve the run live to Foxglove (its WebSocket protocol) on 127.0.0.1 port " +
                                std::to_string(kDefaultFoxglovePort) +
                                " (--foxglove=PORT for another; 0: any free port); the same channels as --mcap");
  cmd->add_option("--foxglove-address", o->foxglove_address,
                  "With --foxglove: the address to serve on (default 127.0.0.1: this machine only; another lets "
                  "anyone who can reach it see the run)")
      ->needs(foxglove.option());
  const PortOption viewer(*cmd, "--viewer", kDefaultViewerPort,
                          "Serve a live view of the run in a web browser, on 127.0.0.1 port " +
                              std::to_string(kDefaultViewerPort) +
                              " (--viewer=PORT for another; 0: any free port); its address is printed");
  cmd->add_option("--viewer-address", o->viewer_address,
                  "With --viewer: the address to serve on (default 127.0.0.1: this machine only; another lets "
                  "anyone who can reach it watch and pause the run)")
      ->needs(viewer.option());
  cmd->add_option("--viewer-origin", o->viewer_origins,
                  "With --viewer: also let pages at ORIGIN (http://HOST[:PORT] or https://HOST[:PORT]; repeatable) "
                  "open the view, and answer to its host: for a name or a proxy in front of the viewer (default: "
                  "only the viewer's own page at a loopback or, with --viewer-address, IP address)")
      ->type_name("ORIGIN")
      ->check(CLI::Validator(ViewerOriginError, "", "origin"))
      ->needs(viewer.option());
  return [o, viewer, foxglove] {
    o->viewer_port = viewer.port();
    o->foxglove_port = foxglove.port();
    const RunSummary s = RunSequence(*o);
    std::printf("%s\n", FormatSummary(s).c_str());
    return s.stopped_by ? 128 + s.stopped_by : kExitOk;  // the shell's status for a stop by that signal
  };
}

}  // namespace sgslam::app
