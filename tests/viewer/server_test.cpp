// The viewer's server (viewer/src/server.h) with a real client over loopback: its
// files and nothing else, the pull protocol, and a bad or stuck page costing only
// its own connection. Who may connect, and the pause a page holds, are
// server_access_test.cpp's.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "server.h"
#include "server_client.h"
#include "server_fixture.h"
#include "sgslam/common/error.h"

namespace sgslam::viewer {
namespace {

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
