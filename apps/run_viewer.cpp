#include "run_viewer.h"

#include <spdlog/spdlog.h>

#include "sgslam/common/error.h"
#include "stop_signals.h"

#ifdef SGSLAM_WITH_VIEWER
#include "live_source.h"
#include "origin.h"
#include "server.h"
#endif

namespace sgslam::app {

#ifdef SGSLAM_WITH_VIEWER

struct RunViewer::Impl {
  Impl(SlamSystem& system, nlohmann::json info, Trajectory truth)
      : source(system, std::move(info), std::move(truth)) {}
  viewer::LiveSource source;
  std::unique_ptr<viewer::Server> server;
};

RunViewer::RunViewer(SlamSystem& system, const std::string& address, int port, nlohmann::json info,
                     Trajectory truth, std::vector<std::string> origins) {
  system.EnableSnapshots();
  impl_ = std::make_unique<Impl>(system, std::move(info), std::move(truth));
  viewer::ServerOptions options;
  options.address = address;
  options.port = static_cast<std::uint16_t>(port);
  options.allowed_origins = std::move(origins);
  impl_->server = std::make_unique<viewer::Server>(options, impl_->source);
  impl_->source.set_server(impl_->server.get());
  spdlog::info("viewer: open {} in a web browser", impl_->server->url());
}

RunViewer::~RunViewer() {
  if (!impl_) return;
  impl_->server.reset();  // before the source it reads
}

void RunViewer::AddFrame(const FrameReport& report) { impl_->source.AddFrame(report); }

void RunViewer::WaitWhilePaused() {
  viewer::PauseControl& pause = impl_->source.pause();
  while (!pause.MayGo()) {
    if (!StopSignals::WaitUntil(std::chrono::steady_clock::time_point::max(), pause.wake_fd())) return;
  }
}

std::string ViewerOriginError(const std::string& text) {
  return viewer::ParseOrigin(text) ? "" : "'" + text + "' is not an origin (http://HOST[:PORT] or https://HOST[:PORT])";
}

#else

struct RunViewer::Impl {};

RunViewer::RunViewer(SlamSystem&, const std::string&, int, nlohmann::json, Trajectory, std::vector<std::string>) {
  throw InputError("--viewer: this sgslam was built without the viewer (CMake option SGSLAM_VIEWER=OFF)");
}
RunViewer::~RunViewer() = default;
void RunViewer::AddFrame(const FrameReport&) {}
void RunViewer::WaitWhilePaused() {}
// Every text passes: without the viewer, run --viewer and view are refused, with the
// reason, when they start.
std::string ViewerOriginError(const std::string&) { return ""; }

#endif

}  // namespace sgslam::app
