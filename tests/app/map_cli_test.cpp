// Map reuse as a user meets it: `sgslam run --save-map`, `sgslam map info` and
// `sgslam run --load-map`, and a clear error for every file or setting that cannot
// be used.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "support/shared_folder.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::RunSgslam;
using test::TempDir;

void ExpectFailure(const std::vector<std::string>& args, std::initializer_list<std::string> parts) {
  const auto r = RunSgslam(args);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  for (const auto& p : parts) EXPECT_NE(r.output.find(p), std::string::npos) << "'" << p << "' not in: " << r.output;
}

// A short static sequence mapped once, with its map saved, for all the tests of
// this file (test::SharedFolder: seq/, room.map, out/); tmp is the test's own.
struct Mapped {
  fs::path shared, seq, map;
  TempDir tmp;
  Mapped()
      : shared(test::SharedFolder("static-mapped",
                                  [](const fs::path& dir) {
                                    const auto s = RunSgslam({"synth", "--preset", "static", "--frames", "40", "--out",
                                                              (dir / "static").string()});
                                    if (s.exit_code != 0) throw std::runtime_error("sgslam synth: " + s.output);
                                    const auto r = RunSgslam({"run", "--dataset", (dir / "static").string(), "--out",
                                                              (dir / "out").string(), "--mode", "none", "--sequential",
                                                              "--save-map", (dir / "room.map").string()});
                                    if (r.exit_code != 0) throw std::runtime_error("sgslam run: " + r.output);
                                  })),
        seq(shared / "static"),
        map(shared / "room.map") {}
  std::vector<std::string> Run(const std::string& out) const {
    return {"run", "--dataset", seq.string(), "--out", (tmp / out).string(), "--mode", "none", "--sequential"};
  }
};

TEST(MapCommand, SaveInfoAndLoad) {
  const Mapped m;
  ASSERT_TRUE(fs::exists(m.map));
  std::ifstream stats_file(m.shared / "out" / "stats.json");
  const auto stats = nlohmann::json::parse(stats_file);
  EXPECT_EQ(stats["map_file"]["saves"], 1);
  const auto info = RunSgslam({"map", "info", m.map.string()});
  ASSERT_EQ(info.exit_code, 0) << info.output;
  for (const char* part : {"MB", "format version 2", "keyframes", "map points", "semantic map"}) {
    EXPECT_NE(info.output.find(part), std::string::npos) << part << " not in " << info.output;
  }
  auto args = m.Run("again");
  args.insert(args.end(), {"--load-map", m.map.string()});
  const auto again = RunSgslam(args);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("loaded"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("40 frames: 40 tracked"), std::string::npos) << again.output;
}

TEST(MapCommand, FilesAndSettingsThatCannotBeUsedAreRefused) {
  const Mapped m;
  // A damaged file.
  const fs::path cut = m.tmp / "cut.map";
  fs::copy_file(m.map, cut);
  fs::resize_file(cut, fs::file_size(m.map) / 2);
  ExpectFailure({"map", "info", cut.string()}, {"cut.map", "truncated"});
  auto load_cut = m.Run("cut");
  load_cut.insert(load_cut.end(), {"--load-map", cut.string()});
  ExpectFailure(load_cut, {"cut.map", "truncated"});
  ExpectFailure({"map", "info", (m.tmp / "none.map").string()}, {"none.map", "not found"});
  // Not a map at all.
  test::WriteText(m.tmp / "text.map", "hello\n");
  ExpectFailure({"map", "info", (m.tmp / "text.map").string()}, {"text.map"});
  // Another camera, no place recognition.
  test::WriteText(m.tmp / "fx.yaml", "camera:\n  fx: 600\n");
  auto other = m.Run("fx");
  other.insert(other.end(), {"--config", (m.tmp / "fx.yaml").string(), "--load-map", m.map.string()});
  ExpectFailure(other, {"room.map", "camera.fx"});
  test::WriteText(m.tmp / "noloop.yaml", "loop:\n  enabled: false\n");
  auto no_loop = m.Run("noloop");
  no_loop.insert(no_loop.end(), {"--config", (m.tmp / "noloop.yaml").string(), "--load-map", m.map.string()});
  ExpectFailure(no_loop, {"loop.enabled"});
  // Saving where a folder is: refused before any frame is processed.
  fs::create_directories(m.tmp / "folder.map");
  auto to_folder = m.Run("folder");
  to_folder.insert(to_folder.end(), {"--save-map", (m.tmp / "folder.map").string()});
  ExpectFailure(to_folder, {"folder.map", "is a folder"});
  EXPECT_FALSE(fs::exists(m.tmp / "folder" / "trajectory.txt"));
}

}  // namespace
}  // namespace sgslam
