#include "sgslam/config/config.h"

#include <gtest/gtest.h>

#include "sgslam/camera/presets.h"
#include "sgslam/common/error.h"
#include "sgslam/config/yaml_io.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

using test::TempDir;
using test::WriteText;

std::string ErrorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, DefaultsAreValid) { EXPECT_NO_THROW(Config{}.Validate("defaults")); }

TEST(Config, LoadsValuesAndKeepsTheRest) {
  TempDir tmp;
  WriteText(tmp / "c.yaml", "camera:\n  fx: 500.5\n  width: 320\n  cx: 100\ndataset:\n  prefetch: 7\n");
  Config c;
  LoadConfigFile(tmp / "c.yaml", c);
  EXPECT_DOUBLE_EQ(c.camera.fx, 500.5);
  EXPECT_EQ(c.camera.width, 320);
  EXPECT_EQ(c.dataset.prefetch, 7);
  EXPECT_DOUBLE_EQ(c.camera.fy, CameraConfig{}.fy);
}

// A misspelt key would otherwise run with the default silently: every unknown key
// and section is listed, with its line and the nearest known name.
TEST(Config, UnknownKeysAreErrorsWithTheirLineAndTheNearestName) {
  TempDir tmp;
  WriteText(tmp / "c.yaml", "camera:\n  fxx: 1\norb:\n  featurs: 900\nnot_a_section:\n  a: 1\n");
  Config c;
  const std::string e = ErrorOf([&] { LoadConfigFile(tmp / "c.yaml", c); });
  EXPECT_NE(e.find("c.yaml:2: unknown key 'camera.fxx' (did you mean 'fx'?)"), std::string::npos) << e;
  EXPECT_NE(e.find("c.yaml:4: unknown key 'orb.featurs' (did you mean 'features'?)"), std::string::npos) << e;
  EXPECT_NE(e.find("c.yaml:5: unknown section 'not_a_section'"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown_keys: warn"), std::string::npos) << "says how to ignore them: " << e;
}

TEST(Config, AFileMayAskForWarningsInstead) {
  TempDir tmp;
  WriteText(tmp / "c.yaml", "unknown_keys: warn\ncamera:\n  fxx: 1\n  fy: 400\nnot_a_section:\n  a: 1\n");
  Config c;
  EXPECT_NO_THROW(LoadConfigFile(tmp / "c.yaml", c));
  EXPECT_DOUBLE_EQ(c.camera.fx, CameraConfig{}.fx);
  EXPECT_DOUBLE_EQ(c.camera.fy, 400);
  WriteText(tmp / "d.yaml", "unknown_keys: maybe\n");
  EXPECT_NE(ErrorOf([&] { LoadConfigFile(tmp / "d.yaml", c); }).find("unknown_keys must be error or warn"),
            std::string::npos);
}

TEST(Config, TypeErrorsNameFileLineAndKey) {
  TempDir tmp;
  WriteText(tmp / "c.yaml", "camera:\n  fx: 500\n  width: 640.5\n");
  Config c;
  const std::string e = ErrorOf([&] { LoadConfigFile(tmp / "c.yaml", c); });
  EXPECT_NE(e.find("c.yaml:3"), std::string::npos) << e;
  EXPECT_NE(e.find("camera.width must be an integer"), std::string::npos) << e;
  WriteText(tmp / "big.yaml", "orb:\n  features: 4294967346\n");  // wrapped round to 50 before
  const std::string big = ErrorOf([&] { LoadConfigFile(tmp / "big.yaml", c); });
  EXPECT_NE(big.find("big.yaml:2"), std::string::npos) << big;
  EXPECT_NE(big.find("orb.features = 4294967346 is out of range"), std::string::npos) << big;
  WriteText(tmp / "d.yaml", "camera:\n  fy: abc\n");
  const std::string e2 = ErrorOf([&] { LoadConfigFile(tmp / "d.yaml", c); });
  EXPECT_NE(e2.find("camera.fy must be a number, got 'abc'"), std::string::npos) << e2;
  WriteText(tmp / "e.yaml", "camera: [1, 2]\n");
  EXPECT_NE(ErrorOf([&] { LoadConfigFile(tmp / "e.yaml", c); }).find("section 'camera' must be a map"),
            std::string::npos);
  WriteText(tmp / "f.yaml", "camera:\n  fx: [1\n");
  EXPECT_NE(ErrorOf([&] { LoadConfigFile(tmp / "f.yaml", c); }).find("cannot parse config file"), std::string::npos);
  EXPECT_NE(ErrorOf([&] { LoadConfigFile(tmp / "missing.yaml", c); }).find("missing.yaml"), std::string::npos);
}

TEST(Config, ValidateListsEveryBadValueWithItsKey) {
  Config c;
  c.camera.fx = -1;
  c.camera.fps = 0;
  c.dataset.prefetch = 0;
  const std::string e = ErrorOf([&] { c.Validate("my.yaml"); });
  EXPECT_NE(e.find("my.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("camera.fx = -1: must be > 0"), std::string::npos) << e;
  EXPECT_NE(e.find("camera.fps = 0"), std::string::npos) << e;
  EXPECT_NE(e.find("dataset.prefetch = 0"), std::string::npos) << e;
}

// Values that pass "> 0" and still break the geometry (a crash, before this check).
TEST(Config, FocalLengthAndDepthFactorMustBePlausibleAndFinite) {
  Config c;
  c.camera.fx = 1e-300;
  c.camera.fy = INFINITY;
  c.camera.depth_factor = std::nan("");
  const std::string e = ErrorOf([&] { c.Validate("my.yaml"); });
  EXPECT_NE(e.find("camera.fx = 1e-300: must be a focal length in pixels"), std::string::npos) << e;
  EXPECT_NE(e.find("camera.fy = inf: must be a finite number > 0"), std::string::npos) << e;
  EXPECT_NE(e.find("camera.depth_factor = nan: must be a finite number > 0"), std::string::npos) << e;
}

TEST(Config, PrintedYamlLoadsBackToTheSameValues) {
  Config a;
  a.camera.fx = 123.456789012;
  a.camera.k1 = -0.25;
  a.dataset.prefetch = 9;
  TempDir tmp;
  WriteText(tmp / "a.yaml", ConfigToYaml(a));
  Config b;
  LoadConfigFile(tmp / "a.yaml", b);
  EXPECT_EQ(ConfigToYaml(a), ConfigToYaml(b));
  EXPECT_DOUBLE_EQ(b.camera.fx, a.camera.fx);
}

TEST(Config, ShippedConfigFilesMatchTheBuiltInPresets) {
  for (const std::string& name : CameraPresetNames()) {
    Config c;
    LoadConfigFile(test::SourceDir() / "configs" / (name + ".yaml"), c);
    c.Validate(name);
    Config p;
    p.camera = *CameraPreset(name);
    EXPECT_EQ(ConfigToYaml(c), ConfigToYaml(p)) << name;
  }
}

}  // namespace
}  // namespace sgslam
