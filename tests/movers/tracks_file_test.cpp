// tracks.txt: written and read back; a malformed line names the file and line.
#include "sgslam/movers/tracks_file.h"

#include <gtest/gtest.h>

#include "sgslam/common/error.h"
#include "support/test_support.h"

namespace sgslam::movers {
namespace {

TEST(TracksFile, RoundTrip) {
  test::TempDir dir;
  TrackLine a;
  a.t = 1'305'031'229'528'748'000;
  a.id = 3;
  a.class_name = "person";
  a.position = {0.1234, -1.5, 2.25};
  a.velocity = {0.5, 0, -0.125};
  a.extent = {0.5, 1.7, 0.3};
  a.state = TrackState::kConfirmed;
  TrackLine b = a;
  b.id = 4, b.class_name = kUnknownClass, b.state = TrackState::kLost;
  WriteTracksFile(dir / "tracks.txt", {a, b});
  const std::vector<TrackLine> read = ReadTracksFile(dir / "tracks.txt");
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].t, a.t);
  EXPECT_EQ(read[0].id, 3);
  EXPECT_EQ(read[0].class_name, "person");
  EXPECT_TRUE(read[0].position.isApprox(a.position, 1e-4));
  EXPECT_TRUE(read[0].velocity.isApprox(a.velocity, 1e-3));
  EXPECT_TRUE(read[0].extent.isApprox(a.extent, 1e-3));
  EXPECT_EQ(read[0].state, TrackState::kConfirmed);
  EXPECT_EQ(read[1].class_name, "unknown");
  EXPECT_EQ(read[1].state, TrackState::kLost);
}

TEST(TracksFile, RefusesMalformedLinesNamingThem) {
  test::TempDir dir;
  const auto expect_refused = [&](const std::string& line, const std::string& what) {
    test::WriteText(dir / "t.txt", "# comment\n" + line + "\n");
    try {
      ReadTracksFile(dir / "t.txt");
      ADD_FAILURE() << "accepted: " << line;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find("t.txt:2"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_refused("1.0 1 person 0 0 0 0 0 0 0 0 0", "13 fields");
  expect_refused("1.0 1 person 0 0 0 0 0 0 0 0 0 moving", "bad state");
  expect_refused("1.0 -2 person 0 0 0 0 0 0 0 0 0 lost", "bad id");
  expect_refused("x 1 person 0 0 0 0 0 0 0 0 0 lost", "bad timestamp");
  expect_refused("1.0 1 person 0 zero 0 0 0 0 0 0 0 lost", "position");
  EXPECT_THROW(ReadTracksFile(dir / "missing.txt"), InputError);
}

}  // namespace
}  // namespace sgslam::movers
