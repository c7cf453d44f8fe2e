#include "run_foxglove.h"

#include <spdlog/spdlog.h>

#include "sgslam/common/error.h"

#ifdef SGSLAM_WITH_VIEWER
#include <thread>

#include "foxglove_server.h"
#include "sgslam/common/bounded_queue.h"
#include "sgslam/common/thread_name.h"
#endif

namespace sgslam::app {

#ifdef SGSLAM_WITH_VIEWER

namespace {

// The channels, numbered from 1 in foxglove::Channels()' order.
std::vector<viewer::FoxgloveChannel> ChannelList() {
  std::vector<viewer::FoxgloveChannel> out;
  for (const foxglove::ChannelInfo& c : foxglove::Channels()) {
    using C = foxglove::Channel;
    const bool map = c.channel == C::kTrajectory || c.channel == C::kMapPoints || c.channel == C::kCloud ||
                     c.channel == C::kObjects;
    out.push_back({static_cast<std::uint32_t>(c.channel) + 1, c.topic, "json", c.schema, foxglove::SchemaText(c.schema),
                   "jsonschema", map});
  }
  return out;
}

std::uint32_t IdOf(foxglove::Channel c) { return static_cast<std::uint32_t>(c) + 1; }

void Publish(viewer::FoxgloveServer& server, std::vector<foxglove::Message>& messages) {
  for (foxglove::Message& m : messages) {
    server.Publish(IdOf(m.channel), static_cast<std::uint64_t>(std::max<Timestamp>(0, m.t)), std::move(m.json));
  }
  messages.clear();
}

std::unique_ptr<viewer::FoxgloveServer> Listen(const std::string& address, int port) {
  auto server = std::make_unique<viewer::FoxgloveServer>(address, static_cast<std::uint16_t>(port), "sgslam", ChannelList());
  spdlog::info("foxglove: in Foxglove, open a connection (Foxglove WebSocket) to {}", server->url());
  return server;
}

}  // namespace

struct RunFoxglove::Impl {
  Impl(SlamSystem& s, const std::string& address, int port, const CameraConfig& camera)
      : system(s), encoder(camera), server(Listen(address, port)) {}

  // The thread's: the frames as they come, the map as its pacer says when someone
  // shows it; only the channels someone subscribed to are made.
  void Run() {
    NameThisThread("sg-foxglove-pub");
    LowerThisThreadsPriority();  // a display must not slow tracking down
    std::vector<foxglove::Message> messages;
    while (auto f = frames.Pop()) {
      try {
        const foxglove::Encoder::Wanted wanted = Wanted();
        encoder.Frame(**f, messages, wanted);
        Publish(*server, messages);
        const Timestamp t = (*f)->t;
        if (map_pacer.Due(t)) PublishMap(t, false, wanted);
      } catch (const std::exception& e) {
        spdlog::error("foxglove: {}", e.what());
      }
    }
  }

  foxglove::Encoder::Wanted Wanted() const {
    foxglove::Encoder::Wanted wanted;
    for (const foxglove::ChannelInfo& c : foxglove::Channels()) {
      wanted.set(static_cast<std::size_t>(c.channel), server->Subscribed(IdOf(c.channel)));
    }
    return wanted;
  }

  void PublishMap(Timestamp t, bool final, const foxglove::Encoder::Wanted& wanted) {
    using C = foxglove::Channel;
    const auto want = [&](C c) { return wanted.test(static_cast<std::size_t>(c)); };
    if (!final && !want(C::kTrajectory) && !want(C::kMapPoints) && !want(C::kObjects) && !want(C::kCloud)) {
      return;  // no snapshot of the map for nobody
    }
    const MapSnapshot map = system.SnapshotMap();
    const std::optional<bool> cloud = map_pacer.Take(map, t, final, want(C::kCloud));
    if (!cloud) return;
    std::vector<foxglove::Message> messages;
    encoder.Map(map, t, *cloud, messages, wanted);
    Publish(*server, messages);
  }

  SlamSystem& system;
  foxglove::Encoder encoder;
  std::unique_ptr<viewer::FoxgloveServer> server;
  // Live: the newest frame matters, one waiting is replaced by the next.
  BoundedQueue<std::shared_ptr<const FrameSnapshot>> frames{1, Overflow::kDropOldest};
  std::thread thread;
  bool finished = false;
  foxglove::MapPacer map_pacer;  // the thread's
  Timestamp last_t = 0;  // the run thread's: the last frame's time
};

RunFoxglove::RunFoxglove(SlamSystem& system, const std::string& address, int port, const CameraConfig& camera)
    : impl_(std::make_unique<Impl>(system, address, port, camera)) {
  system.EnableSnapshots();
  impl_->thread = std::thread([this] { impl_->Run(); });
}

RunFoxglove::~RunFoxglove() { Finish(); }

void RunFoxglove::AddFrame() {
  if (auto f = impl_->system.LatestFrame()) {
    impl_->last_t = f->t;
    impl_->frames.Push(std::move(f));
  }
}

void RunFoxglove::Finish() {
  if (impl_->finished) return;
  impl_->finished = true;
  impl_->frames.Shutdown();
  impl_->thread.join();
  try {  // every map channel, for the clients that connect or subscribe later
    impl_->PublishMap(impl_->last_t + 1, true, foxglove::Encoder::All());  // replaces the updates of the last frame
  } catch (const std::exception& e) {
    spdlog::error("foxglove: {}", e.what());
  }
  if (const std::uint64_t dropped = impl_->server->dropped(); dropped > 0) {
    spdlog::info("foxglove: {} messages not sent to clients that fell behind", dropped);
  }
}

struct ViewFoxglove::Impl {
  std::unique_ptr<viewer::FoxgloveServer> server;
};

ViewFoxglove::ViewFoxglove(const MapSnapshot& map, Timestamp t, const std::string& address, int port,
                           const CameraConfig& camera)
    : impl_(std::make_unique<Impl>()) {
  impl_->server = Listen(address, port);
  std::vector<foxglove::Message> messages;
  foxglove::Encoder(camera).Map(map, t, true, messages);
  Publish(*impl_->server, messages);  // kept by the server for every subscriber
}

ViewFoxglove::~ViewFoxglove() = default;

#else

struct RunFoxglove::Impl {};
RunFoxglove::RunFoxglove(SlamSystem&, const std::string&, int, const CameraConfig&) {
  throw InputError("--foxglove: this sgslam was built without the viewer (CMake option SGSLAM_VIEWER=OFF)");
}
RunFoxglove::~RunFoxglove() = default;
void RunFoxglove::AddFrame() {}
void RunFoxglove::Finish() {}

struct ViewFoxglove::Impl {};
ViewFoxglove::ViewFoxglove(const MapSnapshot&, Timestamp, const std::string&, int, const CameraConfig&) {
  throw InputError("--foxglove: this sgslam was built without the viewer (CMake option SGSLAM_VIEWER=OFF)");
}
ViewFoxglove::~ViewFoxglove() = default;

#endif

}  // namespace sgslam::app
