// What `sgslam view` reads of a finished run (viewer/src/run_folder_files.h and
// run_folder_source.h), on damaged files (issue #47): JSON of the wrong type, an
// OctoMap whose tree lies, a cloud claiming 150 million points, a FIFO. Each is an
// InputError naming the file, never a library's exception or a crash.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <octomap/OcTree.h>

#include "run_folder_files.h"
#include "run_folder_source.h"
#include "sgslam/common/error.h"
#include "support/reader_faults.h"
#include "support/test_support.h"

namespace sgslam::viewer {
namespace {

namespace fs = std::filesystem;
using test::ExpectAll;
using test::RefusalOf;
using test::TempDir;

TEST(RunFolderFiles, StatsOfTheWrongJsonTypeAreNamed) {
  const TempDir tmp;
  test::WriteText(tmp / "stats.json", "[1, 2, 3]");
  ExpectAll(RefusalOf<InputError>([&] { ReadRunStats(tmp / "stats.json"); }), {"stats.json", "a JSON array, not"});
  test::WriteText(tmp / "stats.json", "42");
  ExpectAll(RefusalOf<InputError>([&] { ReadRunStats(tmp / "stats.json"); }), {"stats.json", "a JSON number"});
  test::WriteText(tmp / "stats.json", R"({"dataset": 5, "mode": "sg"})");
  ExpectAll(RefusalOf<InputError>([&] { ReadRunStats(tmp / "stats.json"); }), {"stats.json", "'dataset' must be"});
  test::WriteText(tmp / "stats.json", R"({"dataset": "/d/seq", "frames": "many"})");
  ExpectAll(RefusalOf<InputError>([&] { ReadRunStats(tmp / "stats.json"); }), {"stats.json", "'frames' must be a count"});
  test::WriteText(tmp / "stats.json", R"({"mode": "sg", "frames": -3})");
  ExpectAll(RefusalOf<InputError>([&] { ReadRunStats(tmp / "stats.json"); }), {"'frames' must be a count"});
  test::WriteText(tmp / "stats.json", "{\"mode\": \"\xff\xfe\"}");  // not UTF-8, which JSON text must be
  ExpectAll(RefusalOf<InputError>([&] { ReadRunStats(tmp / "stats.json"); }), {"stats.json", "not valid JSON"});
  test::WriteText(tmp / "stats.json", R"({"dataset": "/d/seq", "mode": "sg", "frames": 12, "other": [1]})");
  const RunStatsInfo info = ReadRunStats(tmp / "stats.json");
  EXPECT_EQ(info.dataset, "/d/seq");
  EXPECT_EQ(info.mode, "sg");
  EXPECT_EQ(info.frames, 12u);
}

TEST(RunFolderFiles, ObjectsOfTheWrongJsonTypeAreNamed) {
  const TempDir tmp;
  test::WriteText(tmp / "objects.json", "[]");
  ExpectAll(RefusalOf<InputError>([&] { ReadRunObjects(tmp / "objects.json"); }), {"objects.json", "a JSON array"});
  test::WriteText(tmp / "objects.json", R"({"objects": {"class": "cup"}})");
  ExpectAll(RefusalOf<InputError>([&] { ReadRunObjects(tmp / "objects.json"); }), {"'objects' must be a list"});
  test::WriteText(tmp / "objects.json", R"({"objects": [{"class": 3, "confidence": 1, "centroid": [0,0,0], "size": [1,1,1]}]})");
  ExpectAll(RefusalOf<InputError>([&] { ReadRunObjects(tmp / "objects.json"); }), {"objects.json: object 1"});
  test::WriteText(tmp / "objects.json", "{not json");
  ExpectAll(RefusalOf<InputError>([&] { ReadRunObjects(tmp / "objects.json"); }), {"objects.json", "not valid JSON"});
}

// A small OctoMap as octomap's writer writes it: a few occupied cells.
std::string OctoMapBytes() {
  octomap::OcTree tree(0.1);
  // Cell centres, far from the cells' borders.
  for (int i = 0; i < 5; ++i) tree.updateNode(octomap::point3d(0.05f + 0.2f * static_cast<float>(i), 0.55f, 1.05f), true);
  std::ostringstream out;
  tree.writeBinary(out);
  return out.str();
}

TEST(RunFolderFiles, AWholeOctoMapIsRead) {
  const TempDir tmp;
  test::WriteText(tmp / "octomap.bt", OctoMapBytes());
  EXPECT_EQ(ReadOccupiedCells(tmp / "octomap.bt").size(), 5u * 4u);
}

TEST(RunFolderFiles, AnOctoMapWhoseTreeLiesIsRefusedBeforeOctoMapReadsIt) {
  const TempDir tmp;
  const std::string whole = OctoMapBytes();
  const auto refusal = [&](const std::string& bytes) {
    test::WriteText(tmp / "octomap.bt", bytes);
    return RefusalOf<InputError>([&] { ReadOccupiedCells(tmp / "octomap.bt"); });
  };
  ExpectAll(refusal(whole.substr(0, whole.size() - 3)), {"octomap.bt", "cut short"});
  ExpectAll(refusal(whole + "xx"), {"octomap.bt", "2 bytes after its node tree"});
  std::string size = whole;
  const std::size_t at = size.find("\nsize ") + 6;
  size.replace(at, size.find('\n', at) - at, "7");
  ExpectAll(refusal(size), {"octomap.bt", "header says 7 nodes"});
  // Every child with children, on and on: OctoMap's reader recurses once a node,
  // and on 4 MiB of these its stack overflows (a crash of sgslam view).
  const std::string header = whole.substr(0, whole.find("\ndata\n") + 6);
  ExpectAll(refusal(header + std::string(4 << 20, '\xff')), {"octomap.bt", "deeper than OctoMap's 16 levels"});
  ExpectAll(refusal("# Octomap OcTree binary file\nid OcTree\nsize 1\nres 0\ndata\n\0\0"), {"resolution"});
  ExpectAll(refusal("not an octomap\n"), {"octomap.bt", "not a binary OctoMap"});
}

TEST(RunFolderSource, AFileOfTheWrongKindOrALyingCloudIsNamed) {
  const TempDir tmp;
  test::WriteText(tmp / "trajectory.txt", "1.0 0 0 0 0 0 0 1\n2.0 0.1 0 0 0 0 0 1\n");
  EXPECT_NO_THROW(RunFolderSource source(tmp.path()));
  test::WriteText(tmp / "cloud.ply",
             "ply\nformat binary_little_endian 1.0\nelement vertex 150000000\nproperty float x\n"
             "property float y\nproperty float z\nend_header\n" + std::string(100, '\0'));
  ExpectAll(RefusalOf<InputError>([&] { RunFolderSource source(tmp.path()); }),
            {"cloud.ply", "claims 150000000 points"});
  fs::remove(tmp / "cloud.ply");
  test::MakeFifo(tmp / "octomap.bt");
  ExpectAll(RefusalOf<InputError>([&] { RunFolderSource source(tmp.path()); }, 10, tmp / "octomap.bt"),
            {"octomap.bt", "FIFO"});
  fs::remove(tmp / "octomap.bt");
  test::WriteText(tmp / "stats.json", "[]");
  ExpectAll(RefusalOf<InputError>([&] { RunFolderSource source(tmp.path()); }), {"stats.json", "a JSON array"});
}

}  // namespace
}  // namespace sgslam::viewer
