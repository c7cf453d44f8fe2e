// Who may use the viewer's server (viewer/src/server.h, origin.h), with a real
// client over loopback: the WebSocket for its own page (or an allowed origin's)
// only, files only for its hosts, each kind of refusal logged once; and a pause
// that ends with the pages that held it.
#include <gtest/gtest.h>
#include <poll.h>

#include <chrono>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include "live_source.h"
#include "server.h"
#include "server_client.h"
#include "server_fixture.h"
#include "sgslam/common/error.h"
#include "sgslam/config/config.h"
#include "sgslam/system/slam_system.h"

namespace sgslam::viewer {
namespace {

// A client's masked WebSocket text frame, payload under 126 bytes.
std::string MaskedText(const std::string& text) {
  const char mask[4] = {1, 2, 3, 4};
  std::string frame = {'\x81', static_cast<char>(0x80 | text.size()), mask[0], mask[1], mask[2], mask[3]};
  for (std::size_t i = 0; i < text.size(); ++i) frame += static_cast<char>(text[i] ^ mask[i % 4]);
  return frame;
}

// An upgrade to /ws with these Host and Origin headers: the server's answer. With
// then_pause, a page's {"control":"pause"} follows at once (in the same write),
// and the connection is read to its end: the server is done with it on return.
http::status TryUpgrade(std::uint16_t port, const std::string& host, const std::optional<std::string>& origin,
                        bool then_pause = false) {
  net::io_context ioc;
  beast::tcp_stream stream(ioc);
  stream.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  http::request<http::empty_body> req(http::verb::get, "/ws", 11);
  req.set(http::field::host, host);
  if (origin) req.set(http::field::origin, *origin);
  req.set(http::field::upgrade, "websocket");
  req.set(http::field::connection, "Upgrade");
  req.set(http::field::sec_websocket_key, "dGhlIHNhbXBsZSBub25jZQ==");
  req.set(http::field::sec_websocket_version, "13");
  std::ostringstream bytes;
  bytes << req << (then_pause ? MaskedText(R"({"control":"pause"})") : "");
  net::write(stream, net::buffer(bytes.str()));
  stream.expires_after(std::chrono::seconds(20));
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(stream, buffer, res);
  beast::error_code ec;
  for (char c; then_pause && !ec;) stream.read_some(net::buffer(&c, 1), ec);
  EXPECT_TRUE(!then_pause || ec != beast::error::timeout) << "the server kept the connection of " << host;
  return res.result();
}

TEST(ViewerServer, OpensTheWebSocketOnlyForItsOwnPage) {
  Fixture f;
  Server server(f.options, f.source);
  const std::string port = std::to_string(server.port()), own = Loopback(server.port());
  struct Attempt {
    std::string host;
    std::optional<std::string> origin;
  };
  for (const Attempt& a : std::vector<Attempt>{
           {own, "http://127.0.0.1:1"},                       // a page of another server on this machine
           {own, "http://evil.example"},                      // another site's page
           {own, std::nullopt},                               // no Origin: not a browser's page
           {own, "null"},                                     // a sandboxed or file:// page
           {own, "https://" + own},                           // not the page's scheme
           {"192.168.1.7:" + port, "http://192.168.1.7:" + port},  // not a loopback host
           {"evil.example:" + port, "http://evil.example:" + port},  // DNS rebinding: Origin == Host
           {"127.0.0.1:1", "http://127.0.0.1:1"},             // another port
           {"127.0.0.1", "http://127.0.0.1"},                 // port 80
           {"", "http://" + own}}) {
    EXPECT_EQ(TryUpgrade(server.port(), a.host, a.origin, /*then_pause=*/true), http::status::forbidden)
        << "Host " << a.host << ", Origin " << a.origin.value_or("(none)");
  }
  EXPECT_TRUE(f.source.Controls().empty());  // none reached the source
  for (const std::string& host : {own, "localhost:" + port, "[::1]:" + port, "127.8.9.10:" + port}) {
    EXPECT_EQ(TryUpgrade(server.port(), host, "http://" + host), http::status::switching_protocols) << host;
  }
  EXPECT_EQ(TryUpgrade(server.port(), "LocalHost:" + port, "http://localhost:" + port),
            http::status::switching_protocols);
}

TEST(ViewerServer, AnswersFileRequestsOnlyForItsHosts) {
  Fixture f;
  Server server(f.options, f.source);
  const std::string port = std::to_string(server.port());
  const auto rebound = Get(server.port(), "/", http::verb::get, "evil.example:" + port);
  EXPECT_EQ(rebound.result(), http::status::forbidden);
  EXPECT_EQ(rebound.body(), "forbidden: not a host this viewer answers to\n");
  EXPECT_EQ(Get(server.port(), "/", http::verb::get, "10.0.0.1:" + port).result(), http::status::forbidden);
  EXPECT_EQ(Get(server.port(), "/", http::verb::get, "localhost:" + port).result(), http::status::ok);
}

TEST(ViewerServer, LogsEachKindOfRefusalOnce) {
  const auto sink = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(64);
  const auto previous = spdlog::default_logger();
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("test", sink));
  {
    Fixture f;
    Server server(f.options, f.source);
    const std::string own = Loopback(server.port());
    for (int i = 0; i < 5; ++i) {
      TryUpgrade(server.port(), own, "http://evil.example:" + std::to_string(i), true);
      TryUpgrade(server.port(), own, std::nullopt, true);
      TryUpgrade(server.port(), "evil.example:" + std::to_string(server.port()), "http://" + own, true);
    }
  }
  spdlog::set_default_logger(previous);
  const std::vector<std::string> lines = sink->last_formatted();
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_NE(lines[0].find("from a page at 'http://evil.example:0'"), std::string::npos) << lines[0];
  EXPECT_NE(lines[1].find("without an Origin"), std::string::npos) << lines[1];
  EXPECT_NE(lines[2].find("for host 'evil.example:"), std::string::npos) << lines[2];
}

TEST(ViewerServer, AllowedOriginsOpenItToTheirPages) {
  Fixture f;
  f.options.allowed_origins = {"http://viewer.example:8080", "HTTPS://Proxy.example/"};
  Server server(f.options, f.source);
  const std::string own = Loopback(server.port());
  const auto upgrade = [&](const std::string& host, const std::string& origin) {
    return TryUpgrade(server.port(), host, origin);
  };
  EXPECT_EQ(upgrade("viewer.example:8080", "http://viewer.example:8080"), http::status::switching_protocols);
  // A proxy that sends its upstream's Host:
  EXPECT_EQ(upgrade(own, "https://proxy.example"), http::status::switching_protocols);
  EXPECT_EQ(upgrade("proxy.example", "https://proxy.example"), http::status::switching_protocols);
  EXPECT_EQ(upgrade("proxy.example:443", "https://proxy.example"), http::status::switching_protocols);
  EXPECT_EQ(upgrade(own, "http://" + own), http::status::switching_protocols);  // its own page still
  EXPECT_EQ(upgrade("viewer.example:8080", "http://evil.example"), http::status::forbidden);
  EXPECT_EQ(upgrade("viewer.example", "http://viewer.example"), http::status::forbidden);  // port 80
  EXPECT_EQ(upgrade("evil.example:" + std::to_string(server.port()), "https://proxy.example"),
            http::status::forbidden);
  EXPECT_EQ(Get(server.port(), "/", http::verb::get, "viewer.example:8080").result(), http::status::ok);

  for (const std::string bad : {"viewer.example", "ftp://viewer.example", "http://viewer.example/path",
                                "http://user@viewer.example", "http://viewer.example:0", "http://viewer.example:99999",
                                "http://", "http://[::1", "null"}) {
    ServerOptions o = f.options;
    o.allowed_origins = {bad};
    try {
      Server refused(o, f.source);
      ADD_FAILURE() << bad << " was taken for an origin";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("'" + bad + "'"), std::string::npos) << e.what();
    }
  }
}

// The run's thread waits for this (RunViewer::WaitWhilePaused), as here.
bool WaitReadable(int fd) {
  pollfd p{fd, POLLIN, 0};
  return poll(&p, 1, 20000) == 1;
}

void WaitForClients(const Server& server, std::size_t n) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (server.clients() != n && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_EQ(server.clients(), n);
}

TEST(ViewerServer, APauseEndsWithThePagesThatHeldIt) {
  Fixture f;
  Config config;
  config.loop.enabled = false;
  config.semantic.enabled = false;
  SlamSystem system(config, /*sequential=*/true);
  LiveSource live(system, {{"live", true}, {"pausable", true}});
  Server server(f.options, live);
  PauseControl& pause = live.pause();
  std::optional<Client> a(server.port()), b(server.port());
  a->Send(R"({"control":"pause"})");
  a->Send(R"({"get":"info"})");
  EXPECT_EQ(a->Receive()["paused"], true);
  EXPECT_FALSE(pause.MayGo());
  b->Send(R"({"control":"step"})");
  b->Send(R"({"get":"info"})");
  EXPECT_EQ(b->Receive()["paused"], true);
  EXPECT_TRUE(pause.MayGo());  // the step
  EXPECT_FALSE(pause.MayGo());

  a.reset();  // b holds the pause still
  WaitForClients(server, 1);
  EXPECT_FALSE(pause.MayGo());
  b->Send(R"({"get":"info"})");
  EXPECT_EQ(b->Receive()["paused"], true);
  b.reset();  // the last holder: the run goes on, and the waiting thread is woken
  ASSERT_TRUE(WaitReadable(pause.wake_fd()));
  EXPECT_TRUE(pause.MayGo());
  EXPECT_FALSE(pause.paused());

  // "resume" from any page ends every hold.
  Client c(server.port()), d(server.port()), e(server.port());
  c.Send(R"({"control":"pause"})");
  d.Send(R"({"control":"pause"})");
  d.Send(R"({"get":"info"})");
  c.Send(R"({"get":"info"})");
  EXPECT_EQ(d.Receive()["paused"], true);
  EXPECT_EQ(c.Receive()["paused"], true);
  e.Send(R"({"control":"resume"})");
  e.Send(R"({"get":"info"})");
  EXPECT_EQ(e.Receive()["paused"], false);
  EXPECT_TRUE(pause.MayGo());
}

}  // namespace
}  // namespace sgslam::viewer
