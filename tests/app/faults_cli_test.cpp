// Regressions found by the fault-injection suite (scripts/faults.py): an output of
// `sgslam run` that cannot be written keeps none of the others back, scoring data
// that cannot be read costs no output, a result that cannot reach stdout is an
// error, closed standard streams never take an output file's place, a bad count is
// refused and a stop signal ends a --realtime wait.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/test_support.h"
#include "support/tiny_dataset.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::RunSgslam;
using test::ShellQuote;
using test::TempDir;

// A short rendered sequence with ground-truth masks, tracked from its first frame.
fs::path Rendered(const TempDir& tmp) {
  const fs::path seq = tmp / "seq";
  const auto r = RunSgslam({"synth", "--preset", "static", "--frames", "6", "--out", seq.string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return seq;
}

nlohmann::json Stats(const fs::path& out) {
  std::ifstream in(out / "stats.json");
  return in ? nlohmann::json::parse(in) : nlohmann::json();
}

std::string Shell(const TempDir& tmp, const std::string& args) {
  return ShellQuote(SGSLAM_BINARY) + " run --dataset " + ShellQuote((tmp / "seq").string()) + " --out " +
         ShellQuote((tmp / "out").string()) + " " + args;
}

// cloud.ply, octomap.bt, objects.json and map_top.png were written as one step: the
// first that failed (a full disk stops the 1 MB cloud first) took the small ones along.
TEST(FaultsCli, EachSemanticOutputIsWrittenOnItsOwn) {
  TempDir tmp;
  Rendered(tmp);
  fs::create_directories(tmp / "out" / "cloud.ply");
  const auto r = RunSgslam({"run", "--dataset", (tmp / "seq").string(), "--out", (tmp / "out").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("outputs not written: cloud.ply"), std::string::npos) << r.output;
  for (const char* f : {"octomap.bt", "objects.json", "map_top.png", "stats.json"}) {
    EXPECT_TRUE(fs::is_regular_file(tmp / "out" / f)) << f;
  }
  EXPECT_EQ(Stats(tmp / "out")["failed_outputs"], nlohmann::json::array({"cloud.ply"}));
}

// The semantic scores reread the keyframes' masks after the frames: a mask that
// does not read ended the run there, before stats.json was written.
TEST(FaultsCli, AnUnreadableTruthMaskCostsNoOutput) {
  TempDir tmp;
  const fs::path seq = Rendered(tmp);
  std::ifstream list(seq / "mask.txt");
  std::string line;
  while (std::getline(list, line) && line.front() == '#') {
  }
  const fs::path mask = seq / line.substr(line.find(' ') + 1);
  fs::remove(mask);
  test::WriteText(mask, "not a png\n");
  const auto r = RunSgslam({"run", "--dataset", seq.string(), "--out", (tmp / "out").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("cannot read dynamic mask"), std::string::npos) << r.output;
  const auto stats = Stats(tmp / "out");
  ASSERT_FALSE(stats.is_null()) << r.output;
  EXPECT_EQ(stats["ended"].get<std::string>().rfind("failed: cannot read dynamic mask", 0), 0u) << stats["ended"];
  EXPECT_TRUE(fs::is_regular_file(tmp / "out" / "trajectory.txt"));
}

// eval --json on a full disk printed nothing and exited 0.
TEST(FaultsCli, AResultThatCannotReachStdoutIsAnError) {
  TempDir tmp;
  const std::string gt = ShellQuote((Rendered(tmp) / "groundtruth.txt").string());
  const auto r = test::RunShell(ShellQuote(SGSLAM_BINARY) + " eval --json --gt " + gt + " --est " + gt +
                                " 2>&1 >/dev/full; echo \"status $?\"");
  EXPECT_NE(r.output.find("cannot write to standard output"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("status 1"), std::string::npos) << r.output;
}

// With stdout and stderr closed, the run's files take descriptors 1 and 2 unless
// they are reopened: a log line or the summary would then land in an output.
TEST(FaultsCli, ClosedStandardStreamsLeaveTheOutputsWhole) {
  TempDir tmp;
  Rendered(tmp);
  const auto r = test::RunShell(Shell(tmp, ">&- 2>&-") + "; echo \"status $?\"");
  EXPECT_NE(r.output.find("status 0"), std::string::npos) << r.output;
  EXPECT_EQ(Stats(tmp / "out")["ended"], "completed");
  std::ifstream trajectory(tmp / "out" / "trajectory.txt");
  std::string line;
  while (std::getline(trajectory, line)) EXPECT_TRUE(line[0] == '#' || std::isdigit(line[0]) || line[0] == '-') << line;
}

// CLI11 read a count beyond 64 bits as 2^64 - 1 and ran every frame.
TEST(FaultsCli, AFrameCountBeyond64BitsIsAUsageError) {
  TempDir tmp;
  const auto r = RunSgslam({"run", "--dataset", tmp.path().string(), "--max-frames", "99999999999999999999999"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--max-frames"), std::string::npos) << r.output;
}

// --realtime waits for each frame's time: a SIGTERM during a wait of an hour (a gap
// in the timestamps) was held until the hour was over.
TEST(FaultsCli, AStopSignalEndsARealtimeWait) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 2);
  std::ofstream(tmp / "seq" / "rgb.txt", std::ios::app) << "4600.000000 rgb/1000.000000.png\n";
  std::ofstream(tmp / "seq" / "depth.txt", std::ios::app) << "4600.005000 depth/1000.005000.png\n";
  const auto r = test::RunShell(Shell(tmp, "--realtime --mode none") +
                                " & p=$!; sleep 2; kill -TERM $p; for i in $(seq 100); do kill -0 $p 2>/dev/null || "
                                "break; sleep 0.1; done; kill -KILL $p 2>/dev/null && echo hung; wait $p; "
                                "echo \"status $?\"");
  EXPECT_EQ(r.output.find("hung"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("status 143"), std::string::npos) << r.output;
  EXPECT_EQ(Stats(tmp / "out")["ended"], "interrupted by SIGTERM");
}

}  // namespace
}  // namespace sgslam
