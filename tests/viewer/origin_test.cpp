// Who may use the viewer (viewer/src/origin.h): origins and Host headers as
// browsers send them, and the rules for a loopback server, one on another
// address, and allowed origins. The server's use of them: server_test.cpp.
#include <gtest/gtest.h>

#include "origin.h"
#include "sgslam/common/error.h"

namespace sgslam::viewer {
namespace {

using Verdict = AccessRules::Verdict;

TEST(ViewerOrigin, ParsesOriginsAsBrowsersWriteThem) {
  const auto o = ParseOrigin("HTTP://Viewer.Example:8080/");
  ASSERT_TRUE(o);
  EXPECT_EQ(o->scheme, "http");
  EXPECT_EQ(o->host, "viewer.example");
  EXPECT_EQ(o->port, 8080);
  EXPECT_EQ(o->ToString(), "http://viewer.example:8080");
  EXPECT_EQ(ParseOrigin("https://viewer.example")->port, 443);
  EXPECT_EQ(ParseOrigin("https://viewer.example:443")->ToString(), "https://viewer.example");
  EXPECT_EQ(ParseOrigin("http://[::1]:7117")->host, "[::1]");
  for (const char* bad : {"", "null", "viewer.example", "ws://viewer.example", "http://", "http://viewer.example/ws",
                          "http://viewer.example//", "http://a@viewer.example", "http://viewer.example:",
                          "http://viewer.example:0", "http://viewer.example:65536", "http://viewer.example:80x",
                          "http://[::1", "http://[not-v6]:80", "http://viewer.example?x", "http://ex ample"}) {
    EXPECT_FALSE(ParseOrigin(bad)) << bad;
  }
}

TEST(ViewerOrigin, ParsesHostHeaders) {
  EXPECT_EQ(ParseHostHeader("127.0.0.1:7117")->port, 7117);
  EXPECT_FALSE(ParseHostHeader("localhost")->port);
  EXPECT_EQ(ParseHostHeader("[::1]:7117")->host, "[::1]");
  for (const char* bad : {"", ":7117", "[::1", "a/b:1", "localhost:7117:1", "localhost:-1"}) {
    EXPECT_FALSE(ParseHostHeader(bad)) << bad;
  }
}

TEST(ViewerOrigin, ALoopbackServerAnswersToLoopbackHostsAtItsPort) {
  const AccessRules rules(/*loopback=*/true, 7117, {});
  for (const char* host : {"127.0.0.1:7117", "127.1.2.3:7117", "localhost:7117", "LOCALHOST:7117", "[::1]:7117"}) {
    EXPECT_EQ(rules.CheckHost(host), Verdict::kAllowed) << host;
  }
  for (const char* host : {"127.0.0.1", "127.0.0.1:7118", "192.168.1.7:7117", "[::2]:7117", "evil.example:7117",
                           "localhost.:7117", "127.0.0.1.evil.example:7117", ""}) {
    EXPECT_EQ(rules.CheckHost(host), Verdict::kUnknownHost) << host;
  }
}

TEST(ViewerOrigin, AServerOnAnotherAddressAnswersToIpAddressesNotNames) {
  const AccessRules rules(/*loopback=*/false, 7117, {});
  for (const char* host : {"192.168.1.7:7117", "[fe80::1]:7117", "127.0.0.1:7117", "localhost:7117"}) {
    EXPECT_EQ(rules.CheckHost(host), Verdict::kAllowed) << host;
  }
  for (const char* host : {"robot.lan:7117", "evil.example:7117", "192.168.1.7:80", "192.168.1.7"}) {
    EXPECT_EQ(rules.CheckHost(host), Verdict::kUnknownHost) << host;
  }
  EXPECT_EQ(rules.CheckUpgrade("192.168.1.7:7117", "http://192.168.1.7:7117"), Verdict::kAllowed);
  EXPECT_EQ(rules.CheckUpgrade("192.168.1.7:7117", "http://192.168.1.8:7117"), Verdict::kForeignOrigin);
  EXPECT_EQ(rules.CheckUpgrade("robot.lan:7117", "http://robot.lan:7117"), Verdict::kUnknownHost);
}

TEST(ViewerOrigin, TheWebSocketIsForThePagesOwnOrigin) {
  const AccessRules rules(true, 7117, {});
  EXPECT_EQ(rules.CheckUpgrade("127.0.0.1:7117", "http://127.0.0.1:7117"), Verdict::kAllowed);
  EXPECT_EQ(rules.CheckUpgrade("localhost:7117", "http://LocalHost:7117"), Verdict::kAllowed);
  EXPECT_EQ(rules.CheckUpgrade("127.0.0.1:7117", std::nullopt), Verdict::kNoOrigin);
  for (const char* origin : {"http://localhost:7117", "http://127.0.0.1:8000", "https://127.0.0.1:7117",
                             "http://127.0.0.1", "null", "http://evil.example"}) {
    EXPECT_EQ(rules.CheckUpgrade("127.0.0.1:7117", std::string_view(origin)), Verdict::kForeignOrigin) << origin;
  }
  EXPECT_EQ(rules.CheckUpgrade("evil.example:7117", "http://evil.example:7117"), Verdict::kUnknownHost);
}

TEST(ViewerOrigin, AllowedOriginsAddTheirHostsAndPages) {
  const AccessRules rules(true, 7117, {"https://viewer.example", "http://127.0.0.1:8000"});
  EXPECT_EQ(rules.CheckHost("viewer.example"), Verdict::kAllowed);
  EXPECT_EQ(rules.CheckHost("viewer.example:443"), Verdict::kAllowed);
  EXPECT_EQ(rules.CheckHost("viewer.example:7117"), Verdict::kUnknownHost);
  EXPECT_EQ(rules.CheckUpgrade("viewer.example", "https://viewer.example"), Verdict::kAllowed);
  EXPECT_EQ(rules.CheckUpgrade("127.0.0.1:7117", "https://viewer.example"), Verdict::kAllowed);  // through a proxy
  EXPECT_EQ(rules.CheckUpgrade("viewer.example", "http://viewer.example"), Verdict::kForeignOrigin);
  // A port forward (ssh -L 8000:127.0.0.1:7117): the browser's Host and Origin name 8000.
  EXPECT_EQ(rules.CheckUpgrade("127.0.0.1:8000", "http://127.0.0.1:8000"), Verdict::kAllowed);
  try {
    AccessRules(true, 7117, {"https://viewer.example", "viewer.example:80"});
    ADD_FAILURE() << "a host without a scheme was taken for an origin";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'viewer.example:80'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sgslam::viewer
