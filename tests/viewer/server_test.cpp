// The viewer's server (viewer/src/server.h) with a real client over loopback: its
// files and nothing else, the pull protocol, and a bad or stuck page costing only
// its own connection.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <mutex>
#include <thread>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "message.h"
#include "server.h"
#include "sgslam/common/error.h"
#include "support/test_support.h"

namespace sgslam::viewer {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

class FakeSource : public Source {
 public:
  std::uint64_t FrameVersion() const override { return version; }
  std::shared_ptr<const std::string> EncodeFrame() override {
    MessageBuilder m("frame");
    m.header()["version"] = version.load();
    return m.Finish();
  }
  std::shared_ptr<const std::string> EncodeMap(const MapRequest& request) override {
    ++maps;
    MessageBuilder m("map");
    m.header()["pieces_after"] = request.pieces_after;
    m.header()["cells_have"] = request.cells_have;
    m.Add("points", std::vector<float>(map_floats, 1.f));
    return m.Finish();
  }
  nlohmann::json Info() const override { return {{"live", true}, {"dataset", "fake"}}; }
  bool Control(const std::string& what) override {
    std::lock_guard lock(mutex);
    controls.push_back(what);
    return true;
  }
  std::vector<std::string> Controls() {
    std::lock_guard lock(mutex);
    return controls;
  }
  std::atomic<std::uint64_t> version{0};
  std::atomic<int> maps{0};
  std::size_t map_floats = 3;
  std::mutex mutex;
  std::vector<std::string> controls;
};

struct Fixture {
  Fixture() {
    std::ofstream(dir / "index.html") << "<!doctype html><title>t</title>";
    std::ofstream(dir / "app.js") << "export {};";
    std::filesystem::create_directories(dir / "three");
    std::ofstream(dir / "three" / "lib.js") << "export {};";
    std::ofstream(dir / ".hidden") << "secret";
    std::ofstream(dir.path().parent_path() / (dir.path().filename().string() + "-outside.txt")) << "secret";
    options.assets = dir.path();
  }
  test::TempDir dir;
  ServerOptions options;
  FakeSource source;
};

http::response<http::string_body> Get(std::uint16_t port, const std::string& target,
                                      http::verb verb = http::verb::get) {
  net::io_context ioc;
  beast::tcp_stream stream(ioc);
  stream.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  http::request<http::empty_body> req(verb, target, 11);
  req.set(http::field::host, "127.0.0.1");
  http::write(stream, req);
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(stream, buffer, res);
  return res;
}

struct Client {
  explicit Client(std::uint16_t port) : ws(ioc) {
    beast::get_lowest_layer(ws).connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
    ws.handshake("127.0.0.1", "/ws");
  }
  void Send(const std::string& text) {
    ws.text(true);
    ws.write(net::buffer(text));
  }
  // The next message's JSON header; throws when the connection is closed.
  nlohmann::json Receive() {
    beast::flat_buffer b;
    ws.read(b);
    const std::string s = beast::buffers_to_string(b.data());
    const std::uint32_t n = static_cast<unsigned char>(s[0]) | static_cast<unsigned char>(s[1]) << 8 |
                            static_cast<unsigned char>(s[2]) << 16 | static_cast<unsigned char>(s[3]) << 24;
    return nlohmann::json::parse(s.substr(4, n));
  }
  bool Closed() {
    try {
      beast::get_lowest_layer(ws).expires_after(std::chrono::seconds(5));
      beast::flat_buffer b;
      ws.read(b);
      return false;
    } catch (const std::exception&) {
      return true;
    }
  }
  net::io_context ioc;
  websocket::stream<beast::tcp_stream> ws;
};

TEST(ViewerServer, ServesItsFilesAndNothingElse) {
  Fixture f;
  Server server(f.options, f.source);
  EXPECT_EQ(Get(server.port(), "/").result(), http::status::ok);
  EXPECT_NE(Get(server.port(), "/").body().find("<title>t</title>"), std::string::npos);
  const auto js = Get(server.port(), "/app.js?v=1");
  EXPECT_EQ(js.result(), http::status::ok);
  EXPECT_EQ(js[http::field::content_type], "text/javascript; charset=utf-8");
  EXPECT_EQ(Get(server.port(), "/three/lib.js").result(), http::status::ok);
  const std::string outside = "/../" + f.dir.path().filename().string() + "-outside.txt";
  for (const std::string& bad : {outside, std::string("/three/../../etc/passwd"), std::string("/%2e%2e/etc/passwd"),
                                 std::string("/.hidden"), std::string("/three"), std::string("/three/"),
                                 std::string("/missing.js"), std::string("//etc/passwd")}) {
    EXPECT_EQ(Get(server.port(), bad).result(), http::status::not_found) << bad;
  }
  EXPECT_EQ(Get(server.port(), "/", http::verb::post).result(), http::status::method_not_allowed);
}

TEST(ViewerServer, RefusesAnAddressItCannotListenOn) {
  Fixture f;
  Server first(f.options, f.source);
  ServerOptions taken = f.options;
  taken.port = first.port();
  EXPECT_THROW(Server(taken, f.source), InputError);
  ServerOptions bad = f.options;
  bad.address = "not-an-address";
  EXPECT_THROW(Server(bad, f.source), InputError);
  ServerOptions local = f.options;  // the name is taken for loopback
  local.address = "localhost";
  EXPECT_NE(Server(local, f.source).port(), 0);
  ServerOptions empty = f.options;
  empty.assets = f.dir / "three";
  EXPECT_THROW(Server(empty, f.source), Error);
}

TEST(ViewerServer, APageGetsANewFrameOnlyWhenThereIsOne) {
  Fixture f;
  Server server(f.options, f.source);
  Client page(server.port());
  page.Send(R"({"get":"info"})");
  EXPECT_EQ(page.Receive()["dataset"], "fake");
  page.Send(R"({"get":"frame","have":0})");  // none yet: the request waits
  page.Send(R"({"get":"map","pieces_after":-1})");
  const nlohmann::json map = page.Receive();
  EXPECT_EQ(map["type"], "map");
  EXPECT_EQ(map["pieces_after"], -1);
  page.Send(R"({"get":"map","pieces_after":12,"cells_have":3})");
  const nlohmann::json map2 = page.Receive();
  EXPECT_EQ(map2["pieces_after"], 12);
  EXPECT_EQ(map2["cells_have"], 3);
  f.source.version = 1;
  server.NotifyFrame();
  const nlohmann::json frame = page.Receive();
  EXPECT_EQ(frame["type"], "frame");
  EXPECT_EQ(frame["version"], 1);
  page.Send(R"({"control":"pause"})");
  page.Send(R"({"get":"frame","have":0})");  // older than the newest: answered at once
  EXPECT_EQ(page.Receive()["version"], 1);
  EXPECT_EQ(f.source.Controls(), std::vector<std::string>{"pause"});
}

TEST(ViewerServer, ABadMessageClosesOnlyItsOwnConnection) {
  Fixture f;
  Server server(f.options, f.source);
  Client good(server.port());
  for (const std::string& bad : {std::string("not json"), std::string(R"({"get":"everything"})"),
                                 std::string(R"({"get":"frame","have":-3})"), std::string(R"([1,2])"),
                                 std::string(R"({"get":"map","pieces_after":1,"cells_have":"x"})"),
                                 std::string(2000, 'x')}) {
    Client page(server.port());
    page.Send(bad);
    EXPECT_TRUE(page.Closed()) << bad.substr(0, 40);
  }
  good.Send(R"({"get":"info"})");
  EXPECT_EQ(good.Receive()["type"], "info");
}

TEST(ViewerServer, APageThatStopsReadingDoesNotHoldUpTheOthers) {
  Fixture f;
  f.source.map_floats = 1 << 20;  // 4 MiB maps
  Server server(f.options, f.source);
  Client stuck(server.port());
  for (int i = 0; i < 50; ++i) stuck.Send(R"({"get":"map","pieces_after":-1})");  // and never reads
  Client page(server.port());
  for (std::uint64_t v = 1; v <= 20; ++v) {
    page.Send(R"({"get":"frame","have":)" + std::to_string(v - 1) + "}");
    f.source.version = v;
    server.NotifyFrame();
    EXPECT_EQ(page.Receive()["version"], v);
  }
  // Every request is read and answered; at most kMaxQueued answers wait for the page.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (f.source.maps.load() < 50 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(f.source.maps.load(), 50);
  EXPECT_EQ(server.clients(), 2u);
}

}  // namespace
}  // namespace sgslam::viewer
