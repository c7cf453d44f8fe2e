// The viewer's command-line options: an allowed origin that is not one
// (run --viewer-origin, view --origin) is a bad command line (exit 2), named.
// What an allowed origin opens: server_test.cpp, and view --origin end to end in
// viewer/tests/cross_origin_test.mjs.
#include <gtest/gtest.h>

#include "support/test_support.h"

namespace sgslam {
namespace {

TEST(ViewerOptions, AnOriginThatIsNotOneIsABadCommandLine) {
  test::TempDir dir;
  for (const std::string bad : {"viewer.example", "ftp://viewer.example", "http://viewer.example/page", "null"}) {
    const auto r = test::RunSgslam({"view", dir.path().string(), "--origin", "http://ok.example", "--origin", bad});
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("'" + bad + "' is not an origin (http://HOST[:PORT] or https://HOST[:PORT])"),
              std::string::npos)
        << r.output;
  }
  // A good one passes the command line: the empty folder is what is refused.
  const auto r = test::RunSgslam({"view", dir.path().string(), "--origin", "https://viewer.example"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("trajectory.txt"), std::string::npos) << r.output;
}

TEST(ViewerOptions, RunTakesAllowedOriginsWithTheViewerOnly) {
  test::TempDir dir;
  const std::string data = dir.path().string();
  const auto bad = test::RunSgslam({"run", "--dataset", data, "--viewer=0", "--viewer-origin", "ftp://x"});
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("'ftp://x' is not an origin"), std::string::npos) << bad.output;
  const auto alone = test::RunSgslam({"run", "--dataset", data, "--viewer-origin", "http://x.example"});
  EXPECT_EQ(alone.exit_code, 2) << alone.output;
  EXPECT_NE(alone.output.find("--viewer-origin requires --viewer"), std::string::npos) << alone.output;
}

}  // namespace
}  // namespace sgslam
