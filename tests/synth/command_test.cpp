// `sgslam synth` as a user runs it.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "sgslam/detection/detections_file.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/io/tum_dataset.h"
#include "sgslam/system/run_config.h"
#include "sgslam/synth/writer.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;

std::string ReadAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

int CountLines(const fs::path& p, bool skip_comments = true) {
  std::ifstream in(p);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) n += !line.empty() && !(skip_comments && line[0] == '#');
  return n;
}

TEST(SynthCommand, WritesEveryListedFile) {
  test::TempDir dir;
  const fs::path out = dir / "seq";
  const auto r = test::RunSgslam({"synth", "--preset", "walkers", "--frames", "10", "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("10 frames"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("walkers"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(out.string()), std::string::npos) << r.output;
  for (const char* f : {"rgb.txt", "depth.txt", "mask.txt", "associations.txt", "groundtruth.txt", "detections.txt",
                        "objects_gt.json", "movers.txt", "sgslam.yaml"}) {
    EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
  }
  for (const char* list : {"rgb.txt", "depth.txt", "mask.txt", "associations.txt"}) EXPECT_EQ(CountLines(out / list), 10) << list;
  EXPECT_EQ(ReadAll(out / "sgslam.yaml"), synth::CameraYaml());
  EXPECT_EQ(ReadAll(out / "rgb.txt").rfind("# color images\n", 0), 0u);

  // The dataset reader of the project opens it, with the camera of sgslam.yaml.
  const RunConfig rc = ResolveRunConfig(std::nullopt, out);
  EXPECT_EQ(rc.config.camera.fx, 525.0);
  EXPECT_EQ(rc.config.camera.k1, 0.0);
  const TumDataset dataset(out, rc.config.dataset);
  ASSERT_EQ(dataset.size(), 10u);
  EXPECT_TRUE(dataset.associations_from_file());
  for (std::size_t i = 0; i < dataset.size(); ++i) {
    const RgbdImages images = dataset.Load(i, rc.config.camera);
    EXPECT_EQ(images.bgr.type(), CV_8UC3);
    EXPECT_EQ(images.depth.type(), CV_16UC1);
    const std::string name = FormatTimestamp(images.t) + ".png";
    EXPECT_EQ(images.t, 1'700'000'000 * kNsPerSecond + static_cast<Timestamp>(std::llround(i * 1e9 / 30 / 1000)) * 1000);
    const cv::Mat mask = cv::imread((out / "mask" / name).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(mask.type(), CV_8UC1) << name;
    EXPECT_EQ(cv::countNonZero(mask == 0) + cv::countNonZero(mask == 255), static_cast<int>(mask.total()));
  }

  const Trajectory gt = ReadTumTrajectory(out / "groundtruth.txt");
  ASSERT_EQ(gt.size(), 10u);
  EXPECT_EQ(gt[3].t, dataset.frames()[3].t_rgb);
  const auto detections = ReadDetectionsFile(out / "detections.txt");
  for (const auto& [t, dets] : detections) {
    for (const Detection& d : dets) EXPECT_EQ(d.class_name, "person");
  }
  const auto json = nlohmann::json::parse(ReadAll(out / "objects_gt.json"));
  ASSERT_GE(json.at("objects").size(), 2u);
  for (const auto& o : json.at("objects")) {
    EXPECT_EQ(o.at("class"), "person");
    EXPECT_TRUE(o.at("dynamic").get<bool>());
    EXPECT_EQ(o.at("size").size(), 3u);
  }
}

TEST(SynthCommand, RefusesANonEmptyFolderUnlessForced) {
  test::TempDir dir;
  const fs::path out = dir / "seq";
  ASSERT_EQ(test::RunSgslam({"synth", "--frames", "2", "--out", out.string()}).exit_code, 0);
  test::WriteText(out / "notes.txt", "mine");
  const auto again = test::RunSgslam({"synth", "--frames", "2", "--out", out.string()});
  EXPECT_EQ(again.exit_code, 1) << again.output;
  EXPECT_NE(again.output.find(out.string()), std::string::npos) << again.output;
  const auto forced = test::RunSgslam({"synth", "--frames", "3", "--preset", "static", "--out", out.string(), "--force"});
  EXPECT_EQ(forced.exit_code, 0) << forced.output;
  EXPECT_EQ(ReadAll(out / "notes.txt"), "mine");  // only our files are replaced
  EXPECT_EQ(CountLines(out / "rgb.txt"), 3);
}

TEST(SynthCommand, BadArgumentsGiveClearErrors) {
  test::TempDir dir;
  const auto preset = test::RunSgslam({"synth", "--preset", "nope", "--out", (dir / "a").string()});
  EXPECT_NE(preset.exit_code, 0);
  EXPECT_NE(preset.output.find("nope"), std::string::npos) << preset.output;
  EXPECT_NE(preset.output.find("rpy, loop or repeat"), std::string::npos) << preset.output;
  const auto noise = test::RunSgslam({"synth", "--depth-noise", "tof", "--out", (dir / "a").string()});
  EXPECT_EQ(noise.exit_code, 2) << noise.output;
  const auto frames = test::RunSgslam({"synth", "--frames", "0", "--out", (dir / "b").string()});
  EXPECT_NE(frames.exit_code, 0);
  EXPECT_NE(frames.output.find("frames"), std::string::npos) << frames.output;
  const auto readout = test::RunSgslam({"synth", "--readout", "0.5", "--out", (dir / "c").string()});
  EXPECT_EQ(readout.exit_code, 1);
  EXPECT_NE(readout.output.find("readout"), std::string::npos) << readout.output;
  EXPECT_FALSE(fs::exists(dir / "a"));
  EXPECT_FALSE(fs::exists(dir / "b"));
  EXPECT_FALSE(fs::exists(dir / "c"));
  EXPECT_NE(test::RunSgslam({"synth", "--frames", "2"}).exit_code, 0);  // --out is required
}

// --readout: a rolling shutter, and a camera in sgslam.yaml that says so; the run
// configuration of the folder reads it back exactly.
TEST(SynthCommand, ARollingShutterSequenceCarriesItsReadout) {
  test::TempDir dir;
  const fs::path out = dir / "rpy";
  const auto r = test::RunSgslam({"synth", "--preset", "rpy", "--frames", "3", "--readout", "0.03", "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(ReadAll(out / "sgslam.yaml"), synth::CameraYaml(0.03));
  EXPECT_NE(ReadAll(out / "sgslam.yaml").find("readout: 0.03  #"), std::string::npos);
  EXPECT_NE(ReadAll(out / "rgb.txt").find("--preset rpy --seed 1 --readout 0.03"), std::string::npos);
  EXPECT_EQ(ResolveRunConfig(std::nullopt, out).config.camera.readout, 0.03);
}

// loop takes its sensor from the preset (a Kinect's depth, a rolling shutter)
// unless told otherwise; rgb.txt names the command either way.
TEST(SynthCommand, PresetDefaultsApplyUnlessOverridden) {
  test::TempDir dir;
  const auto r = test::RunSgslam({"synth", "--preset", "loop", "--frames", "2", "--out", (dir / "a").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("readout 0.03 s, depth noise kinect"), std::string::npos) << r.output;
  EXPECT_EQ(ReadAll(dir / "a" / "sgslam.yaml"), synth::CameraYaml(0.03));
  const std::string source = "'sgslam synth --preset loop --seed 1 --readout 0.03 --depth-noise kinect'";
  EXPECT_NE(ReadAll(dir / "a" / "rgb.txt").find(source), std::string::npos);
  const auto plain = test::RunSgslam({"synth", "--preset", "loop", "--frames", "2", "--readout", "0", "--depth-noise",
                                      "none", "--out", (dir / "b").string()});
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_EQ(ReadAll(dir / "b" / "sgslam.yaml"), synth::CameraYaml(0));
  EXPECT_NE(ReadAll(dir / "b" / "rgb.txt").find("'sgslam synth --preset loop --seed 1 --readout 0 --depth-noise none'"),
            std::string::npos);
}

}  // namespace
}  // namespace sgslam
