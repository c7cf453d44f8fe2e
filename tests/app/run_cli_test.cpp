// `sgslam run` as a user meets it: every bad input ends with a non-zero exit status
// and a message that names the file, line, key or value at fault.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "run_outputs.h"
#include "sgslam/detection/detections_file.h"
#include "support/test_support.h"
#include "support/tiny_dataset.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::RunSgslam;
using test::TempDir;

void ExpectFailure(const std::vector<std::string>& args, int code, std::initializer_list<std::string> parts) {
  const auto r = RunSgslam(args);
  EXPECT_EQ(r.exit_code, code) << r.output;
  for (const auto& p : parts) EXPECT_NE(r.output.find(p), std::string::npos) << "'" << p << "' not in: " << r.output;
}

std::vector<std::string> RunArgs(const TempDir& tmp, const std::string& dataset = "seq") {
  return {"run", "--dataset", (tmp / dataset).string(), "--out", (tmp / "out").string(), "--mode", "none"};
}

fs::path NthFile(const fs::path& dir, std::size_t n) {
  std::vector<fs::path> v(fs::directory_iterator(dir), fs::directory_iterator{});
  std::sort(v.begin(), v.end());
  return v.at(n);
}

TEST(RunCommand, GoodDatasetWritesConfigFramesAndStats) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 4);
  const auto r = RunSgslam(RunArgs(tmp));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Flat images: nothing to track, and the summary says so instead of inventing poses.
  EXPECT_NE(r.output.find("4 frames: 0 tracked"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("no frame was tracked"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("final bundle adjustment"), std::string::npos) << r.output;
  for (const char* f : {"trajectory.txt", "keyframes.txt", "map_points.ply", "config_used.yaml"}) {
    EXPECT_TRUE(fs::exists(tmp / "out" / f)) << f;
  }
  std::ifstream stats_file(tmp / "out" / "stats.json");
  const auto stats = nlohmann::json::parse(stats_file);
  EXPECT_EQ(stats["frames"], 4);
  EXPECT_EQ(stats["tracked"], 0);
  EXPECT_EQ(stats["ended"], "completed");
  std::ifstream csv(tmp / "out" / "frames.csv");
  std::string line;
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 5);  // header + 4 frames
}

// --realtime hands frames over at their timestamps' pace: 10 frames at 30 Hz
// take at least 0.3 s of wall time (a lower bound set by the pacing, not a
// speed figure), and stats.json records the mode.
TEST(RunCommand, RealtimePacesFramesByTheirTimestamps) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 10);
  std::vector<std::string> args = RunArgs(tmp);
  args.push_back("--realtime");
  args.push_back("--every-frame");  // none dropped, however loaded the machine
  const auto r = RunSgslam(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream stats_file(tmp / "out" / "stats.json");
  const auto stats = nlohmann::json::parse(stats_file);
  EXPECT_EQ(stats["realtime"], true);
  EXPECT_EQ(stats["frames"], 10);
  EXPECT_EQ(stats["live"]["dropped"], 0);
  EXPECT_EQ(stats["live"]["every_frame"], true);
  EXPECT_GE(stats["live"]["p95_latency_ms"].get<double>(), stats["live"]["median_latency_ms"].get<double>());
  // fps counts from the first frame to the end: 10 frames spanning 9/30 s.
  EXPECT_LE(stats["fps"].get<double>(), 10.0 / 0.3 + 1e-6);
}

// Like a live camera, --realtime keeps one frame waiting while the system is busy,
// and a newer frame replaces it: 12 frames 10 us apart have all arrived while the
// first is processed, so the last one is taken next and those between are dropped.
TEST(RunCommand, RealtimeDropsFramesThatArriveWhileTheSystemIsBusy) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 12, 10'000);
  std::vector<std::string> args = RunArgs(tmp);
  args.push_back("--realtime");
  const auto r = RunSgslam(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream stats_file(tmp / "out" / "stats.json");
  const auto stats = nlohmann::json::parse(stats_file);
  const int frames = stats["frames"], dropped = stats["live"]["dropped"];
  EXPECT_EQ(frames + dropped, 12);
  EXPECT_GE(dropped, 9);  // frame 0 may be dropped too, when frame 1 has arrived before it starts
  EXPECT_NE(r.output.find("frames dropped"), std::string::npos) << r.output;
  // Without --realtime nothing is ever dropped, and --every-frame needs --realtime.
  const auto bad = RunSgslam({"run", "--dataset", (tmp / "seq").string(), "--every-frame"});
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
}

// A run with a detector saves the boxes it got as detections.txt, in the format of
// the file backend, so a later run (or another tool) can replay them; frames.csv
// counts them and the boxes carried over missed frames apart.
TEST(RunCommand, DetectionsOfTheRunAreSavedForReplay) {
  TempDir tmp;
  const auto synth = RunSgslam({"synth", "--preset", "walkers", "--frames", "12", "--out", (tmp / "walk").string()});
  ASSERT_EQ(synth.exit_code, 0) << synth.output;
  const auto r = RunSgslam(
      {"run", "--dataset", (tmp / "walk").string(), "--out", (tmp / "out").string(), "--mode", "sg", "--sequential"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto saved = ReadDetectionsFile(tmp / "out" / "detections.txt");
  const auto given = ReadDetectionsFile(tmp / "walk" / "detections.txt");
  ASSERT_FALSE(given.empty());
  ASSERT_EQ(saved.size(), given.size());
  for (const auto& [t, boxes] : given) {
    ASSERT_EQ(saved.count(t), 1u);
    const auto& s = saved.at(t);
    ASSERT_EQ(s.size(), boxes.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
      EXPECT_EQ(s[i].class_name, boxes[i].class_name);
      EXPECT_EQ(s[i].box, boxes[i].box);
      EXPECT_EQ(s[i].carried, 0);
    }
  }
  // Every output is one RunOutputNames() gives, which the paths are checked by
  // (io/output_plan.h), and this run, with the detector and the semantic map, wrote them all.
  std::vector<std::string> written;
  for (const auto& e : fs::directory_iterator(tmp / "out")) written.push_back(e.path().filename().string());
  std::vector<std::string> names = app::RunOutputNames();
  std::sort(written.begin(), written.end());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(written, names);
  std::ifstream csv(tmp / "out" / "frames.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find(",detections,carried,"), std::string::npos) << header;
  // The sequence's objects_gt.json (its walkers have no one place) scores the object map.
  std::ifstream stats_file(tmp / "out" / "stats.json");
  const auto stats = nlohmann::json::parse(stats_file);
  EXPECT_TRUE(stats["semantic"].contains("objects_truth")) << r.output;
  EXPECT_EQ(r.output.find("no scores of the object map"), std::string::npos) << r.output;
  // Without a detector there is nothing to save.
  const auto none = RunSgslam(
      {"run", "--dataset", (tmp / "walk").string(), "--out", (tmp / "out2").string(), "--mode", "none", "--sequential"});
  ASSERT_EQ(none.exit_code, 0) << none.output;
  EXPECT_FALSE(fs::exists(tmp / "out2" / "detections.txt"));
}

// budget.cores: a budget no run can keep throttles the detector one level a window
// (every (level + 1)-th frame), says so in frames.csv and stats.json and warns once
// at the top level; a budget of the whole machine changes nothing.
TEST(RunCommand, ACpuBudgetLowersTheDetectorsRate) {
  TempDir tmp;
  const auto synth = RunSgslam({"synth", "--preset", "walkers", "--frames", "160", "--out", (tmp / "walk").string()});
  ASSERT_EQ(synth.exit_code, 0) << synth.output;
  const auto run = [&](const std::string& name, double cores) {
    std::ofstream(tmp / (name + ".yaml")) << "budget:\n  cores: " << cores << "\n";
    const auto r = RunSgslam({"run", "--dataset", (tmp / "walk").string(), "--out", (tmp / name).string(), "--mode",
                              "sg", "--sequential", "--config", (tmp / (name + ".yaml")).string()});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::ifstream stats_file(tmp / name / "stats.json");
    return std::make_pair(nlohmann::json::parse(stats_file), r.output);
  };
  const auto [tight, tight_log] = run("tight", 0.01);
  ASSERT_TRUE(tight.contains("budget")) << tight.dump();
  const nlohmann::json& b = tight["budget"];
  EXPECT_EQ(b["cores"], 0.01);
  EXPECT_EQ(b["windows"], 5);  // 160 frames: the first opens, then 30 a window
  EXPECT_EQ(b["windows_over"], b["windows"]);
  EXPECT_EQ(b["level_max"], 4);
  EXPECT_GT(b["last_cores_used"].get<double>(), 0.01);
  // Levels 1-4 over the windows: the detector ran on far fewer frames than at level 0.
  const int submitted = tight["dynamic"]["detector_submitted"];
  // Level 0 for 31 frames, then 1, 2, 3, 4 for 30 each: 31 + 15 + 10 + 8 + 6 (+1 at each change).
  EXPECT_LT(submitted, 80) << "of 160";
  EXPECT_GT(submitted, 60) << "of 160";
  EXPECT_NE(tight_log.find("budget.cores 0.01: the run needs"), std::string::npos) << tight_log;
  std::ifstream csv(tmp / "tight" / "frames.csv");
  std::string header, line, last;
  std::getline(csv, header);
  EXPECT_EQ(header.substr(header.rfind(',') + 1), "budget_level");
  while (std::getline(csv, line)) last = line;
  EXPECT_EQ(last.substr(last.rfind(',') + 1), "4");

  const auto [loose, loose_log] = run("loose", 64);
  EXPECT_EQ(loose["budget"]["level_max"], 0) << loose.dump();
  EXPECT_EQ(loose["budget"]["windows_over"], 0);
  EXPECT_EQ(loose["dynamic"]["detector_submitted"], 160);
  EXPECT_EQ(loose_log.find("budget.cores"), std::string::npos) << loose_log;
}

TEST(RunCommand, UsageErrorsExitWith2) {
  ExpectFailure({"run"}, 2, {"--dataset"});
  ExpectFailure({"run", "--dataset", "x", "--mode", "magic"}, 2, {"magic"});
  ExpectFailure({"frobnicate"}, 2, {"frobnicate"});
}

TEST(RunCommand, MissingDatasetFolderAndListFile) {
  TempDir tmp;
  ExpectFailure(RunArgs(tmp, "absent"), 1, {"dataset folder not found", "absent"});
  fs::create_directories(tmp / "empty");
  ExpectFailure(RunArgs(tmp, "empty"), 1, {"rgb.txt"});
}

TEST(RunCommand, MalformedLineNamesFileAndLine) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 3);
  std::ofstream(tmp / "seq" / "rgb.txt", std::ios::app) << "123.0\n";
  ExpectFailure(RunArgs(tmp), 1, {"rgb.txt:5", "expected 'timestamp path'"});
}

TEST(RunCommand, EmptySequence) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 2);
  test::WriteText(tmp / "seq" / "rgb.txt", "# color images\n");
  ExpectFailure(RunArgs(tmp), 1, {"empty sequence", "rgb.txt has 0 images"});
}

TEST(RunCommand, MissingAndCorruptImages) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 3);
  const fs::path rgb = NthFile(tmp / "seq" / "rgb", 1);
  fs::remove(rgb);
  ExpectFailure(RunArgs(tmp), 1, {"image missing", rgb.string()});
  test::WriteText(rgb, "garbage");
  ExpectFailure(RunArgs(tmp), 1, {"cannot read image", rgb.string()});
  // A PNG whose header claims 60000x60000 pixels: refused from its header, before
  // anything is decoded (and the frame before it is written).
  std::string png = "\x89PNG\r\n\x1a\n";
  const unsigned char ihdr[] = {0, 0, 0, 13, 'I', 'H', 'D', 'R', 0, 0, 0xEA, 0x60, 0, 0, 0xEA, 0x60, 8, 2, 0, 0, 0};
  png.append(reinterpret_cast<const char*>(ihdr), sizeof ihdr);
  std::uint32_t crc = 0xFFFFFFFFu;  // PNG's CRC-32 of the chunk type and data
  for (std::size_t i = 4; i < sizeof ihdr; ++i) {
    crc ^= ihdr[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  crc = ~crc;
  for (int shift = 24; shift >= 0; shift -= 8) png += static_cast<char>((crc >> shift) & 0xFF);
  test::WriteText(rgb, png);
  ExpectFailure(RunArgs(tmp), 1, {rgb.string() + " is 60000x60000", "outputs of the 1 frames before it"});
  std::ifstream stats_file(tmp / "out" / "stats.json");
  EXPECT_NE(nlohmann::json::parse(stats_file)["ended"].get<std::string>().find("failed: RGB and depth sizes differ"),
            std::string::npos);
}

TEST(RunCommand, DepthOfWrongTypeOrSize) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 2);
  const fs::path depth = NthFile(tmp / "seq" / "depth", 0);
  cv::imwrite(depth.string(), cv::Mat(48, 64, CV_8UC1, cv::Scalar(7)));
  ExpectFailure(RunArgs(tmp), 1, {depth.string(), "8-bit 1-channel", "16-bit single-channel"});
  cv::imwrite(depth.string(), cv::Mat(20, 30, CV_16UC1, cv::Scalar(10000)));
  ExpectFailure(RunArgs(tmp), 1, {"RGB and depth sizes differ", depth.string(), "30x20"});
}

// SIGTERM (what timeout, systemd, docker and roslaunch send) stops the run after the
// frame it is on; every output is written for the frames processed, stats.json says
// how the run ended, and the exit status is the shell's for that signal (128 + 15).
TEST(RunCommand, SigtermStopsTheRunAndKeepsItsOutputs) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 300);  // 10 s at the camera's pace
  std::string command;
  for (const std::string& a : RunArgs(tmp)) command += test::ShellQuote(a) + " ";
  const auto r = test::RunShell(test::ShellQuote(SGSLAM_BINARY) + " " + command +
                                "--realtime 2>&1 & p=$!; sleep 2; kill -TERM $p; wait $p; echo \"status $?\"");
  EXPECT_NE(r.output.find("status 143"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("interrupted by SIGTERM"), std::string::npos) << r.output;
  std::ifstream stats_file(tmp / "out" / "stats.json");
  ASSERT_TRUE(stats_file) << r.output;
  const auto stats = nlohmann::json::parse(stats_file);
  EXPECT_EQ(stats["ended"], "interrupted by SIGTERM");
  EXPECT_GT(stats["frames"].get<int>(), 10);
  EXPECT_LT(stats["frames"].get<int>(), 300);
  for (const char* f : {"trajectory.txt", "keyframes.txt", "map_points.ply", "frames.csv"}) {
    EXPECT_TRUE(fs::exists(tmp / "out" / f)) << f;
  }
}

// One output that cannot be written (here trajectory.txt is a folder) does not keep
// the others back, and no temporary file is left behind.
TEST(RunCommand, AnOutputThatCannotBeWrittenLeavesTheOthers) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 4);
  fs::create_directories(tmp / "out" / "trajectory.txt");
  ExpectFailure(RunArgs(tmp), 1, {"outputs not written: trajectory.txt"});
  for (const char* f : {"keyframes.txt", "map_points.ply", "frames.csv", "stats.json"}) {
    EXPECT_TRUE(fs::is_regular_file(tmp / "out" / f)) << f;
  }
  for (const auto& entry : fs::directory_iterator(tmp / "out")) {
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
  }
  std::ifstream stats_file(tmp / "out" / "stats.json");
  EXPECT_EQ(nlohmann::json::parse(stats_file)["failed_outputs"][0], "trajectory.txt");
}

TEST(RunCommand, WrongDepthScale) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 2);
  std::ofstream(tmp / "seq" / "sgslam.yaml", std::ios::app) << "  depth_factor: 100\n";
  ExpectFailure(RunArgs(tmp), 1, {"median depth of 100 m", "depth_factor"});
}

TEST(RunCommand, BrokenConfigValuesNameKeyAndFile) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 2);
  test::WriteText(tmp / "bad.yaml", "camera:\n  fx: -5\n");
  auto args = RunArgs(tmp);
  args.insert(args.end(), {"--config", (tmp / "bad.yaml").string()});
  ExpectFailure(args, 1, {"bad.yaml", "camera.fx = -5: must be > 0"});
  test::WriteText(tmp / "bad.yaml", "camera:\n  fx: fast\n");
  ExpectFailure(args, 1, {"bad.yaml:2", "camera.fx must be a number"});
  test::WriteText(tmp / "bad.yaml", "orb:\n  featurs: 900\n");
  ExpectFailure(args, 1, {"bad.yaml:2", "unknown key 'orb.featurs'", "did you mean 'features'"});
  args.back() = (tmp / "nope.yaml").string();
  ExpectFailure(args, 1, {"config file not found", "nope.yaml"});
}

TEST(RunCommand, ImageSizeDifferentFromCamera) {
  TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 2);
  fs::remove(tmp / "seq" / "sgslam.yaml");  // falls back to the 640x480 TUM fr1 camera
  ExpectFailure(RunArgs(tmp), 1, {"64x48", "camera.width"});
}

}  // namespace
}  // namespace sgslam
