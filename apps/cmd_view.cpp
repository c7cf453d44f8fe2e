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
#include "run_pipeline.h"
#include "run_viewer.h"
#include "sgslam/common/error.h"
#include "stop_signals.h"

#ifdef SGSLAM_WITH_VIEWER
#include "run_folder_source.h"
#include "server.h"
#endif

namespace sgslam::app {

namespace {

struct ViewOptions {
  std::string folder, address = "127.0.0.1";
  int port = kDefaultViewerPort;
  std::vector<std::string> origins;
};

int View(const ViewOptions& o) {
#ifdef SGSLAM_WITH_VIEWER
  const StopSignals stop;
  viewer::RunFolderSource source(o.folder);
  viewer::ServerOptions options;
  options.address = o.address;
  options.port = static_cast<std::uint16_t>(o.port);
  options.allowed_origins = o.origins;
  viewer::Server server(options, source);
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
  return [o] { return View(*o); };
}

}  // namespace sgslam::app
