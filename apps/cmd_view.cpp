// sgslam view: a finished run's outputs in the viewer's web page, served until
// Ctrl-C.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "commands.h"
#include "port_option.h"
#include "run_foxglove.h"
#include "run_pipeline.h"
#include "run_viewer.h"
#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/io/ply.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/semantic/object_json.h"
#include "stop_signals.h"

#ifdef SGSLAM_WITH_VIEWER
#include "run_folder_files.h"
#include "run_folder_source.h"
#include "server.h"
#endif

namespace sgslam::app {

namespace {

struct ViewOptions {
  std::string folder, address = "127.0.0.1";
  int port = kDefaultViewerPort;
  int foxglove_port = -1;  // --foxglove[=PORT]; -1: none
  std::vector<std::string> origins;
};

#ifdef SGSLAM_WITH_VIEWER
// The run's map as Foxglove's channels show it: keyframes, map points, the dense
// cloud (one piece at the origin) and the objects; the time of its last pose.
MapSnapshot ReadRunMap(const std::filesystem::path& folder, Timestamp& last) {
  MapSnapshot m;
  const Trajectory trajectory = ReadTumTrajectory(folder / "trajectory.txt");  // checked there by the page's source
  last = trajectory.empty() ? 0 : trajectory.back().t;
  if (OptionalRegularFile(folder / "keyframes.txt", "keyframe trajectory")) {
    for (const StampedPose& k : ReadTumTrajectory(folder / "keyframes.txt")) {
      m.keyframes.push_back({m.keyframes.size(), k.t, k.T_w_c});
    }
  }
  if (OptionalRegularFile(folder / "map_points.ply", "map points")) m.points = ReadPlyPoints(folder / "map_points.ply");
  if (OptionalRegularFile(folder / "cloud.ply", "cloud")) {
    std::vector<Rgb> colours;
    const std::vector<Eigen::Vector3d> cloud = ReadPlyPoints(folder / "cloud.ply", &colours);
    auto points = std::make_shared<std::vector<ColoredPoint>>();
    points->reserve(cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      points->push_back({cloud[i].cast<float>(), colours.empty() ? Rgb{200, 200, 200} : colours[i]});
    }
    m.cloud.push_back({0, SE3(), std::move(points)});
  }
  if (const auto objects = folder / "objects.json"; OptionalRegularFile(objects, "run output")) {
    m.objects = ObjectsFromJson(viewer::ReadRunObjects(objects));  // its fields checked there
  }
  return m;
}
#endif

int View(const ViewOptions& o) {
#ifdef SGSLAM_WITH_VIEWER
  const StopSignals stop;
  viewer::RunFolderSource source(o.folder);
  viewer::ServerOptions options;
  options.address = o.address;
  options.port = static_cast<std::uint16_t>(o.port);
  options.allowed_origins = o.origins;
  viewer::Server server(options, source);
  std::unique_ptr<ViewFoxglove> foxglove;
  if (o.foxglove_port >= 0) {
    Timestamp last = 0;
    const MapSnapshot map = ReadRunMap(o.folder, last);
    foxglove = std::make_unique<ViewFoxglove>(map, last, o.address, o.foxglove_port, CameraConfig{});
  }
  spdlog::info("view: {}: open {} in a web browser (Ctrl-C to stop)", o.folder, server.url());
  StopSignals::WaitUntil(std::chrono::steady_clock::time_point::max());
  return kExitOk;
#else
  (void)o;
  throw InputError("view: this sgslam was built without the viewer (CMake option SGSLAM_VIEWER=OFF)");
#endif
}

}  // namespace

Action AddViewCommand(CLI::App& root) {
  auto o = std::make_shared<ViewOptions>();
  CLI::App* cmd = root.add_subcommand("view", "Show a finished run's outputs (an --out folder of run) in a web browser");
  cmd->add_option("folder", o->folder, "The run's output folder (trajectory.txt, map_points.ply, cloud.ply, ...)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--port", o->port, "Port (0: any free port)")->check(CLI::Range(0, 65535));
  cmd->add_option("--address", o->address,
                  "Address to serve on (default 127.0.0.1: this machine only; another lets anyone who can reach it "
                  "see the run)");
  cmd->add_option("--origin", o->origins,
                  "Also let pages at ORIGIN (http://HOST[:PORT] or https://HOST[:PORT]; repeatable) open the view, "
                  "and answer to its host: for a name or a proxy in front of the viewer (default: only this "
                  "viewer's own page at a loopback or, with --address, IP address)")
      ->type_name("ORIGIN")
      ->check(CLI::Validator(ViewerOriginError, "", "origin"));
  const PortOption foxglove(*cmd, "--foxglove", kDefaultFoxglovePort,
                            "Also serve the run's map, trajectory, cloud and objects to Foxglove (its WebSocket "
                            "protocol), port " + std::to_string(kDefaultFoxglovePort) +
                                " (--foxglove=PORT for another; 0: any free port)");
  return [o, foxglove] {
    o->foxglove_port = foxglove.port();
    return View(*o);
  };
}

}  // namespace sgslam::app
