#include "mcap_recorder.h"

#include <spdlog/spdlog.h>

#include "sgslam/common/error.h"
#include "sgslam/common/thread_name.h"

namespace sgslam::app {

McapRecorder::McapRecorder(const std::filesystem::path& file, SlamSystem& system, const CameraConfig& camera,
                           bool live)
    : system_(system),
      writer_(file),
      encoder_(camera),
      frames_(kQueuedFrames, live ? Overflow::kDropOldest : Overflow::kBlock) {
  std::map<std::string, std::uint16_t> schemas;
  for (const foxglove::ChannelInfo& c : foxglove::Channels()) {
    auto [it, added] = schemas.emplace(c.schema, 0);
    if (added) it->second = writer_.AddSchema(c.schema, "jsonschema", foxglove::SchemaText(c.schema));
    channel_ids_[static_cast<std::size_t>(c.channel)] = writer_.AddChannel(it->second, c.topic, "json");
  }
  system.EnableSnapshots();
  thread_ = std::thread([this] { Run(); });
}

McapRecorder::~McapRecorder() {
  if (finished_) return;
  frames_.Shutdown();
  thread_.join();
  writer_.Abandon();
}

void McapRecorder::AddFrame() {
  if (auto f = system_.LatestFrame()) frames_.Push(std::move(f));
}

std::string McapRecorder::Finish() {
  if (finished_) return error_;
  finished_ = true;
  frames_.Shutdown();  // the frames queued are still written
  thread_.join();
  if (!writer_.failed()) {
    try {
      // 1 ns after the last frame: its scene updates replace those of that time.
      if (any_frame_) WriteMap(last_t_ + 1, true);
      writer_.Close();
    } catch (const std::exception& e) {
      error_ = e.what();
    }
  }
  if (frames_.dropped() > 0) {
    spdlog::warn("mcap: {} frames not recorded: they came while {} waited to be written", frames_.dropped(),
                 kQueuedFrames);
  }
  if (skipped_ > 0) spdlog::warn("mcap: {} frames not recorded: their messages could not be made", skipped_);
  if (error_.empty()) {
    spdlog::info("mcap: {} messages, {:.1f} MiB in {}", writer_.messages(), writer_.bytes() / 1048576.0,
                 writer_.path().string());
  }
  return error_;
}

void McapRecorder::Run() {
  NameThisThread("sg-mcap");
  LowerThisThreadsPriority();  // a recording must not slow tracking down
  std::vector<foxglove::Message> messages;
  while (auto f = frames_.Pop()) {
    if (writer_.failed()) continue;  // the run goes on, the frames are let go
    try {
      messages.clear();
      encoder_.Frame(**f, messages);
      Write(messages);
      last_t_ = (*f)->t;
      any_frame_ = true;
      if (map_pacer_.Due(last_t_)) WriteMap(last_t_, false);
    } catch (const std::exception& e) {
      if (writer_.failed()) {
        error_ = e.what();
        spdlog::error("mcap: {}; the recording stops here, the run goes on", error_);
      } else if (skipped_++ == 0) {
        spdlog::warn("mcap: frame {}: {}; left out of the recording", (*f)->index, e.what());
      }
    }
  }
}

void McapRecorder::Write(const std::vector<foxglove::Message>& messages) {
  for (const foxglove::Message& m : messages) {
    const auto t = static_cast<std::uint64_t>(std::max<Timestamp>(0, m.t));
    writer_.Write(channel_ids_[static_cast<std::size_t>(m.channel)], t, t, m.json);
  }
}

void McapRecorder::WriteMap(Timestamp t, bool final) {
  const MapSnapshot map = system_.SnapshotMap();
  const std::optional<bool> cloud = map_pacer_.Take(map, t, final);
  if (!cloud) return;
  std::vector<foxglove::Message> messages;
  encoder_.Map(map, t, *cloud, messages);
  Write(messages);
}

}  // namespace sgslam::app
