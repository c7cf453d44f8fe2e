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
      if (!any_map_ || ToSeconds(last_t_ - map_t_) >= kMapPeriod) WriteMap(last_t_, false);
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
  bytes_ = writer_.bytes();
  messages_ = writer_.messages();
}

// The map when it changed (a keyframe, the semantic thread's cloud), the cloud at
// most every kCloudPeriod; everything at the end.
void McapRecorder::WriteMap(Timestamp t, bool final) {
  map_t_ = t;
  const MapSnapshot map = system_.SnapshotMap();
  if (!final && any_map_ && map.keyframes.size() == map_keyframes_ && map.cloud.size() == map_pieces_) return;
  const bool cloud = final || (map.cloud.size() != map_pieces_ && ToSeconds(t - cloud_t_) >= kCloudPeriod);
  any_map_ = true;
  map_keyframes_ = map.keyframes.size();
  if (cloud) {
    map_pieces_ = map.cloud.size();
    cloud_t_ = t;
  }
  std::vector<foxglove::Message> messages;
  encoder_.Map(map, t, cloud, messages);
  Write(messages);
}

}  // namespace sgslam::app
