// The mover tracks in the viewer's messages (viewer/src/movers.h): a live frame's
// as JSON, a finished run's tracks.txt as the map's buffers, each line at the pose
// of its timestamp, and a damaged tracks.txt named by `sgslam view`.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "movers.h"
#include "run_folder_source.h"
#include "sgslam/common/error.h"
#include "support/reader_faults.h"
#include "support/test_support.h"

namespace sgslam::viewer {
namespace {

using test::ExpectAll;
using test::RefusalOf;
using test::TempDir;

// A message (message.h) taken apart: its header, and each buffer's values.
struct Decoded {
  nlohmann::json header;
  std::map<std::string, std::vector<double>> buffers;
};

Decoded Decode(const std::string& message) {
  std::uint32_t length = 0;
  std::memcpy(&length, message.data(), 4);  // little-endian, as this machine is
  Decoded d;
  d.header = nlohmann::json::parse(message.substr(4, length));
  const std::size_t base = 4 + length + (4 - length % 4) % 4;
  for (const nlohmann::json& b : d.header["buffers"]) {
    const char* at = message.data() + base + b["offset"].get<std::size_t>();
    std::vector<double>& values = d.buffers[b["name"].get<std::string>()];
    for (std::size_t i = 0; i < b["count"].get<std::size_t>(); ++i) {
      if (b["type"] == "f32") {
        float v;
        std::memcpy(&v, at + 4 * i, 4);
        values.push_back(v);
      } else if (b["type"] == "u32") {
        std::uint32_t v;
        std::memcpy(&v, at + 4 * i, 4);
        values.push_back(v);
      } else {
        values.push_back(static_cast<unsigned char>(at[i]));
      }
    }
  }
  return d;
}

TEST(ViewerMovers, AFramesMoversAreItsTracksWithTheirState) {
  MoverSnapshot person{3, "person", movers::TrackState::kConfirmed, {1, 2, 3}, {0.5, 0, 0}, {0.4, 1.7, 0.3}};
  MoverSnapshot unknown{8, "unknown", movers::TrackState::kLost, {-1, 0, 2}, {0, 0, 0}, {0.2, 0.2, 0.2}};
  const nlohmann::json j = MoversJson({person, unknown});
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0]["id"], 3);
  EXPECT_EQ(j[0]["class"], "person");
  EXPECT_EQ(j[0]["state"], "confirmed");
  EXPECT_EQ(j[0]["position"], nlohmann::json({1.0, 2.0, 3.0}));
  EXPECT_EQ(j[0]["extent"], nlohmann::json({0.4, 1.7, 0.3}));
  EXPECT_EQ(j[1]["state"], "lost");
  EXPECT_TRUE(MoversJson({}).is_array());
}

movers::TrackLine Line(double t, int id, const std::string& cls, movers::TrackState state, double x) {
  movers::TrackLine l;
  l.t = FromSeconds(t);
  l.id = id;
  l.class_name = cls;
  l.state = state;
  l.position = {x, 0, 1};
  l.extent = {0.5, 1.5, 0.5};
  return l;
}

TEST(ViewerMovers, ARunsTrackLinesGoToTheirPosesFrameByFrame) {
  const Trajectory trajectory = {{FromSeconds(10.0), SE3()}, {FromSeconds(10.5), SE3()}, {FromSeconds(11.0), SE3()}};
  using movers::TrackState;
  const std::vector<movers::TrackLine> lines = {
      Line(11.0, 4, "person", TrackState::kLost, 0.3),  // out of order: sorted by frame
      Line(10.0, 4, "person", TrackState::kTentative, 0.1),
      Line(10.5, 4, "person", TrackState::kConfirmed, 0.2),
      Line(10.5, 9, "unknown", TrackState::kConfirmed, -1.0),
      Line(10.7, 9, "unknown", TrackState::kConfirmed, -1.1),  // no pose at 10.7 s
  };
  MessageBuilder m("map");
  EXPECT_EQ(AddRunTracks(lines, trajectory, m), 1u);
  const Decoded d = Decode(*m.Finish());
  EXPECT_EQ(d.header["mover_classes"], nlohmann::json({"person", "unknown"}));
  EXPECT_EQ(d.buffers.at("path_t"), (std::vector<double>{0, 0.5, 1}));
  EXPECT_EQ(d.buffers.at("mover_frame"), (std::vector<double>{0, 1, 1, 2}));
  EXPECT_EQ(d.buffers.at("mover_id"), (std::vector<double>{4, 4, 9, 4}));
  EXPECT_EQ(d.buffers.at("mover_class"), (std::vector<double>{0, 0, 1, 0}));
  EXPECT_EQ(d.buffers.at("mover_state"), (std::vector<double>{0, 1, 1, 2}));  // tentative, confirmed, lost
  ASSERT_EQ(d.buffers.at("mover_position").size(), 12u);
  EXPECT_FLOAT_EQ(static_cast<float>(d.buffers.at("mover_position")[3]), 0.2f);
  EXPECT_FLOAT_EQ(static_cast<float>(d.buffers.at("mover_position")[6]), -1.0f);
  EXPECT_FLOAT_EQ(static_cast<float>(d.buffers.at("mover_extent")[1]), 1.5f);
}

TEST(ViewerMovers, ARunFoldersTracksAreInItsMapAndADamagedFileIsNamed) {
  const TempDir tmp;
  test::WriteText(tmp / "trajectory.txt", "1.000000 0 0 0 0 0 0 1\n1.033333 0.1 0 0 0 0 0 1\n");
  {
    RunFolderSource source(tmp.path());  // without tracks.txt: no movers
    EXPECT_EQ(Decode(*source.EncodeMap({})).buffers.count("mover_id"), 0u);
  }
  test::WriteText(tmp / "tracks.txt",
                  "# timestamp id class x y z vx vy vz sx sy sz state\n"
                  "1.033333 2 person 0.5 0 1.5 0.1 0 0 0.4 1.6 0.3 confirmed\n");
  RunFolderSource source(tmp.path());
  const Decoded d = Decode(*source.EncodeMap({}));
  EXPECT_EQ(d.buffers.at("mover_id"), std::vector<double>{2});
  EXPECT_EQ(d.buffers.at("mover_frame"), std::vector<double>{1});
  EXPECT_EQ(d.header["mover_classes"], nlohmann::json({"person"}));
  test::WriteText(tmp / "tracks.txt", "1.033333 2 person 0.5 0 1.5 0.1 0 0 0.4 1.6 0.3 walking\n");
  ExpectAll(RefusalOf<InputError>([&] { RunFolderSource damaged(tmp.path()); }),
            {"tracks.txt:1", "bad state 'walking'"});
  test::WriteText(tmp / "tracks.txt", "1.033333 2 person 0.5 0 1.5\n");
  ExpectAll(RefusalOf<InputError>([&] { RunFolderSource damaged(tmp.path()); }), {"tracks.txt:1", "13 fields"});
}

}  // namespace
}  // namespace sgslam::viewer
