// `sgslam eval` run as a user runs it: exit codes, messages, JSON and the plot.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "sgslam/eval/evaluate.h"
#include "sgslam/eval/plot.h"
#include "support/test_support.h"

namespace sgslam::eval {
namespace {

using test::RunSgslam;
using test::TempDir;

// stdout alone (RunSgslam merges stderr), to prove --json prints nothing else there.
std::string RunStdoutOnly(const std::vector<std::string>& args) {
  std::string cmd = SGSLAM_BINARY;
  for (const std::string& a : args) cmd += " '" + a + "'";
  cmd += " 2>/dev/null </dev/null";
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while (pipe && (n = fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  if (pipe) pclose(pipe);
  return out;
}

// gt: 30 s of smooth 3-D motion at 100 Hz; est: every 3rd pose, moved and disturbed.
void WriteInputs(const TempDir& tmp, int n = 3000) {
  Trajectory gt, est;
  const SE3 M(so3::Exp(Eigen::Vector3d(0.1, 0.2, -0.3)), Eigen::Vector3d(1, 2, 3));
  for (int i = 0; i < n; ++i) {
    const double s = i * 0.01;
    const SE3 T(so3::Exp(Eigen::Vector3d(0.2 * std::sin(s), 0.1 * s, 0.3 * std::cos(0.5 * s))),
                Eigen::Vector3d(std::sin(0.3 * s), 0.5 * std::cos(0.2 * s), 0.2 * std::sin(s)));
    gt.push_back({1'305'031'225'000'000'000 + i * 10'000'000LL, T});
    const Eigen::Vector3d wobble(0.02 * std::sin(3.0 * s), 0.01 * std::cos(7.0 * s), 0.015 * std::sin(5.0 * s));
    if (i % 3 == 0) est.push_back({gt.back().t + 3'000'000, M * SE3(T.quaternion(), T.translation() + wobble)});
  }
  WriteTumTrajectory(tmp / "gt.txt", gt);
  WriteTumTrajectory(tmp / "est.txt", est);
}

void ExpectStatsEqual(const nlohmann::json& j, const ErrorStats& s) {
  EXPECT_DOUBLE_EQ(j.at("rmse").get<double>(), s.rmse);
  EXPECT_DOUBLE_EQ(j.at("mean").get<double>(), s.mean);
  EXPECT_DOUBLE_EQ(j.at("median").get<double>(), s.median);
  EXPECT_DOUBLE_EQ(j.at("std").get<double>(), s.std);
  EXPECT_DOUBLE_EQ(j.at("min").get<double>(), s.min);
  EXPECT_DOUBLE_EQ(j.at("max").get<double>(), s.max);
  EXPECT_EQ(j.at("pairs").get<std::size_t>(), s.count);
}

TEST(EvalCommand, JsonOnStdoutMatchesTheLibrary) {
  TempDir tmp;
  WriteInputs(tmp);
  const std::string gt = (tmp / "gt.txt").string(), est = (tmp / "est.txt").string();
  const std::string out = RunStdoutOnly({"eval", "--gt", gt, "--est", est, "--json", "--delta", "2"});
  const nlohmann::json j = nlohmann::json::parse(out);  // throws on anything but one JSON value
  EvalOptions options;
  options.rpe_delta = 2 * kNsPerSecond;
  const EvalReport r = EvaluateFiles(gt, est, options);
  ExpectStatsEqual(j.at("ate"), r.ate.stats);
  ASSERT_TRUE(r.rpe.has_value());
  EXPECT_DOUBLE_EQ(j.at("rpe").at("delta_s").get<double>(), 2.0);
  EXPECT_EQ(j.at("rpe").at("pairs").get<std::size_t>(), r.rpe->pairs.size());
  ExpectStatsEqual(j.at("rpe").at("trans"), r.rpe->trans);
  ExpectStatsEqual(j.at("rpe").at("rot_deg"), r.rpe->rot_deg);
  EXPECT_EQ(j.at("gt"), gt);
  EXPECT_EQ(j.at("est"), est);
  EXPECT_GT(r.ate.stats.rmse, 0.005);  // the wobble is seen...
  EXPECT_LT(r.ate.stats.rmse, 0.03);   // ...and the rigid motion is not
  EXPECT_EQ(RunSgslam({"eval", "--gt", gt, "--est", est, "--json"}).exit_code, 0);
}

TEST(EvalCommand, TableByDefault) {
  TempDir tmp;
  WriteInputs(tmp);
  const auto r = RunSgslam({"eval", "--gt", (tmp / "gt.txt").string(), "--est", (tmp / "est.txt").string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ATE [m] over 1000 pairs"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("rot [deg]"), std::string::npos) << r.output;
}

TEST(EvalCommand, ShortEstimateStillReportsAte) {
  TempDir tmp;
  WriteInputs(tmp, 60);  // 0.6 s: no pose pair 1 s apart
  const std::string out = RunStdoutOnly(
      {"eval", "--gt", (tmp / "gt.txt").string(), "--est", (tmp / "est.txt").string(), "--json"});
  const nlohmann::json j = nlohmann::json::parse(out);
  EXPECT_EQ(j.at("ate").at("pairs").get<int>(), 20);
  EXPECT_TRUE(j.at("rpe").is_null());
  EXPECT_FALSE(j.at("rpe_note").get<std::string>().empty());
}

TEST(EvalCommand, MissingFileIsNamed) {
  TempDir tmp;
  WriteInputs(tmp, 100);
  const std::string missing = (tmp / "nope" / "est.txt").string();
  const auto r = RunSgslam({"eval", "--gt", (tmp / "gt.txt").string(), "--est", missing});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find(missing), std::string::npos) << r.output;
}

TEST(EvalCommand, MalformedLineIsNamedWithFileAndLine) {
  TempDir tmp;
  WriteInputs(tmp, 100);
  test::WriteText(tmp / "bad.txt", "# header\n1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n3.0 0 0 x 0 0 0 1\n");
  const auto r = RunSgslam({"eval", "--gt", (tmp / "gt.txt").string(), "--est", (tmp / "bad.txt").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find((tmp / "bad.txt").string() + ":4"), std::string::npos) << r.output;
}

TEST(EvalCommand, NoOverlapIsAnError) {
  TempDir tmp;
  WriteInputs(tmp, 100);
  test::WriteText(tmp / "far.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n3.0 0 0 0 0 0 0 1\n");
  const auto r = RunSgslam({"eval", "--gt", (tmp / "gt.txt").string(), "--est", (tmp / "far.txt").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("no pose of " + (tmp / "far.txt").string()), std::string::npos) << r.output;
}

TEST(EvalCommand, PlotIsAReadablePng) {
  TempDir tmp;
  WriteInputs(tmp);
  const std::filesystem::path png = tmp / "plots" / "ate.png";
  const auto r = RunSgslam({"eval", "--gt", (tmp / "gt.txt").string(), "--est", (tmp / "est.txt").string(),
                            "--plot", png.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_GT(std::filesystem::file_size(png), 1000u);
  const cv::Mat img = cv::imread(png.string());
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, AtePlotOptions{}.width);
  EXPECT_EQ(img.rows, AtePlotOptions{}.height);
  EXPECT_FALSE(std::filesystem::exists(png.string() + ".tmp"));
}

TEST(EvalCommand, UnwritablePlotFolderIsNamed) {
  TempDir tmp;
  WriteInputs(tmp, 100);
  const std::string png = "/proc/sgslam-no-such-dir/ate.png";
  const auto r = RunSgslam({"eval", "--gt", (tmp / "gt.txt").string(), "--est", (tmp / "est.txt").string(),
                            "--plot", png, "--json"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find(png), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("\"ate\""), std::string::npos) << "no result is printed when the plot fails";
}

TEST(EvalCommand, BadOptionsAreUsageErrors) {
  EXPECT_EQ(RunSgslam({"eval", "--est", "x.txt"}).exit_code, 2);
  EXPECT_EQ(RunSgslam({"eval", "--gt", "a", "--est", "b", "--delta", "-1"}).exit_code, 2);
  // Beyond what the nanosecond time holds: named as out of range, not "must be positive".
  const auto huge = RunSgslam({"eval", "--gt", "a", "--est", "b", "--delta", "1e10"});
  EXPECT_EQ(huge.exit_code, 2);
  EXPECT_NE(huge.output.find("--delta: Value 1e10 not in range"), std::string::npos) << huge.output;
}

}  // namespace
}  // namespace sgslam::eval
