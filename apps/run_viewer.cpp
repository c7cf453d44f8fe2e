#include "run_viewer.h"

#include <spdlog/spdlog.h>

#include "sgslam/common/error.h"
#include "stop_signals.h"

#ifdef SGSLAM_WITH_VIEWER
#include "live_source.h"
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
                     Trajectory truth) {
  system.EnableSnapshots();
  impl_ = std::make_unique<Impl>(system, std::move(info), std::move(truth));
  viewer::ServerOptions options;
  options.address = address;
  options.port = static_cast<std::uint16_t>(port);
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

#else

struct RunViewer::Impl {};

RunViewer::RunViewer(SlamSystem&, const std::string&, int, nlohmann::json, Trajectory) {
  throw InputError("--viewer: this sgslam was built without the viewer (CMake option SGSLAM_VIEWER=OFF)");
}
RunViewer::~RunViewer() = default;
void RunViewer::AddFrame(const FrameReport&) {}
void RunViewer::WaitWhilePaused() {}

#endif

}  // namespace sgslam::app
