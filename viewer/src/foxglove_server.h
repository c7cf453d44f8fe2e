// A server of Foxglove's WebSocket protocol (foxglove.websocket.v1,
// https://github.com/foxglove/ws-protocol/blob/main/docs/spec.md) on Boost.Beast,
// with a thread of its own (`sg-foxglove`): Foxglove's app, or any client of the
// protocol, connects, is told the channels (serverInfo, advertise), subscribes to
// those it shows, and receives their messages as binary frames.
//
// Publish() never blocks and never waits for a client: a client's messages wait in
// a queue of at most kMaxQueuedBytes, beyond which new ones to it are dropped
// (counted), so a slow client gets fewer messages and one that stops reading costs
// a bounded amount of memory. The last message of a latched channel is kept and
// sent to a new subscriber at once (a map published once a second, or once for a
// finished run, shows as soon as a panel subscribes). Clients are not authenticated: the
// server listens on loopback unless told otherwise (a warning then). A client
// message that is not the protocol's JSON, or over kMaxClientMessage, and a client
// whose replies (status messages) no longer fit its queue, are closed; operations
// the server does not offer are answered with a status warning. On destruction each
// client gets up to kCloseWait to receive what is queued for it, then a close frame.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sgslam::viewer {

struct FoxgloveChannel {
  std::uint32_t id = 0;  // unique, not 0
  std::string topic, encoding, schema_name, schema, schema_encoding;
  bool latched = false;  // its last message is sent to a new subscriber at once (a map, not a frame's)
};

class FoxgloveServer {
 public:
  static constexpr std::size_t kMaxQueuedBytes = 16 << 20;  // waiting for one client
  static constexpr std::size_t kMaxClientMessage = 64 << 10;
  static constexpr std::chrono::milliseconds kCloseWait{2000};

  // Listens at once. Throws InputError naming the address when it cannot (port in
  // use, not an address of this machine).
  FoxgloveServer(const std::string& address, std::uint16_t port, std::string name,
                 std::vector<FoxgloveChannel> channels);
  ~FoxgloveServer();  // closes every connection and joins the thread
  FoxgloveServer(const FoxgloveServer&) = delete;
  FoxgloveServer& operator=(const FoxgloveServer&) = delete;

  std::uint16_t port() const;
  std::string url() const;  // ws://address:port

  // Whether a client is subscribed to the channel (to skip making its messages).
  bool Subscribed(std::uint32_t channel) const;
  // Any thread: the message (the channel's encoding) at time t (ns) to the channel's
  // subscribers, and kept for later ones.
  void Publish(std::uint32_t channel, std::uint64_t t, std::string payload);

  std::uint64_t dropped() const;  // messages not sent to a client that was behind

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace sgslam::viewer
