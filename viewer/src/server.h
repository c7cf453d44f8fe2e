// The live viewer's server: the page's files over HTTP and its data over one
// WebSocket per page (Boost.Beast, one thread of its own, `sg-viewer`).
//
// The page pulls: it asks for the next frame newer than the one it has, and for the
// map when it has drawn the last one. A page that is slow, or stops reading, is
// therefore never sent more than a few messages (and at most kMaxQueued wait for
// it, the oldest dropped first): it cannot slow the run down nor grow memory.
// Security: only the files of `assets` are served (no path outside it, no listing);
// a request or WebSocket message over its size limit, or one that is not the JSON
// the page sends, closes that connection and nothing else. The server answers only
// to the hosts of origin.h's rules, and the WebSocket opens only for its own page
// (or an allowed origin's): other requests get 403, never reaching the Source.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace sgslam::viewer {

// What the page shows. Its functions are called on the server's thread only.
class Source {
 public:
  virtual ~Source() = default;
  // Grows with every new frame (0: none yet). The page sends the version it has.
  virtual std::uint64_t FrameVersion() const = 0;
  // The newest frame as a message (message.h), or null when there is none.
  virtual std::shared_ptr<const std::string> EncodeFrame() = 0;
  // The map. Cloud pieces are sent only for keyframes with ids above pieces_after
  // (the page keeps those it has and moves them with their keyframes' poses), and
  // the OctoMap's cells only when their version is not cells_have.
  struct MapRequest {
    std::int64_t pieces_after = -1;
    std::uint64_t cells_have = 0;
  };
  virtual std::shared_ptr<const std::string> EncodeMap(const MapRequest& request) = 0;
  // What the page's title and panel say of the run ("live", dataset, mode, ...).
  virtual nlohmann::json Info() const = 0;
  // A control from a page ("pause", "resume", "step"). page: its connection's
  // number, given by the server, never reused while it runs. false: not for this
  // source.
  virtual bool Control(const std::string& /*what*/, std::uint64_t /*page*/) { return false; }
  // That page's connection has closed: what it held (a pause) ends with it.
  virtual void PageClosed(std::uint64_t /*page*/) {}
};

struct ServerOptions {
  std::string address = "127.0.0.1";  // or "localhost"; another than loopback is served with a warning
  std::uint16_t port = 0;        // 0: any free port
  std::filesystem::path assets;  // the page's files (index.html, ...); empty: share/sgslam/viewer
  // Origins ("http[s]://host[:port]") of pages elsewhere that may open the
  // WebSocket too, and whose hosts the server answers to: for a name or a proxy in
  // front of it (origin.h).
  std::vector<std::string> allowed_origins;
};

class Server {
 public:
  static constexpr std::size_t kMaxQueued = 4;  // messages waiting for one page

  // Listens at once. Throws sgslam::Error naming the address when it cannot (port
  // taken, address not this machine's), the allowed origin that is not one, or
  // assets when it has no index.html.
  Server(ServerOptions options, Source& source);
  ~Server();  // closes every connection and joins the thread
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  std::uint16_t port() const;
  std::string url() const;  // http://address:port/
  // A new frame is ready: the pages waiting for one get it. Never blocks.
  void NotifyFrame();
  std::size_t clients() const;  // open WebSocket connections

  struct Impl;  // server.cpp's sessions reach it; opaque elsewhere

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace sgslam::viewer
