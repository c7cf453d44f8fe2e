#include "sgslam/config/config.h"

#include <gtest/gtest.h>

#include <set>

#include "sgslam/camera/presets.h"
#include "sgslam/common/error.h"
#include "sgslam/config/removed_keys.h"
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
  WriteText(tmp / "c.yaml",
            "camera:\n  fx: 500.5\n  width: 320\n  cx: 100\ndataset:\n  max_time_difference: 0.04\n"
            "tracking:\n  refinements:\n    trusted_points: false\n");
  Config c;
  LoadConfigFile(tmp / "c.yaml", c);
  EXPECT_DOUBLE_EQ(c.camera.fx, 500.5);
  EXPECT_EQ(c.camera.width, 320);
  EXPECT_DOUBLE_EQ(c.dataset.max_time_difference, 0.04);
  EXPECT_DOUBLE_EQ(c.camera.fy, CameraConfig{}.fy);
  EXPECT_FALSE(c.tracking.refinements.trusted_points);  // a sub-section's key
  EXPECT_TRUE(c.tracking.refinements.rolling_shutter_refine);
}

TEST(Config, SubSectionsAreCheckedLikeSections) {
  TempDir tmp;
  WriteText(tmp / "c.yaml", "tracking:\n  refinements:\n    trusted_point: false\n");
  Config c;
  const std::string e = ErrorOf([&] { LoadConfigFile(tmp / "c.yaml", c); });
  EXPECT_NE(e.find("c.yaml:3: unknown key 'tracking.refinements.trusted_point' (did you mean 'trusted_points'?)"),
            std::string::npos)
      << e;
  WriteText(tmp / "d.yaml", "tracking:\n  refinements: 3\n");
  EXPECT_NE(ErrorOf([&] { LoadConfigFile(tmp / "d.yaml", c); }).find("d.yaml:2: 'tracking.refinements' must be a map"),
            std::string::npos);
}

// A config_used.yaml of an earlier version names keys that are constants now: it
// loads when they hold the values this version uses, and is refused when one asks
// for another, which this version cannot do.
TEST(Config, ARemovedKeyLoadsAtItsLastValueOnly) {
  TempDir tmp;
  WriteText(tmp / "old.yaml", "mapping:\n  busy_frames: 5\n  queue_size: 3.0\ntracking:\n  rolling_shutter_refine: true\n");
  Config c;
  EXPECT_NO_THROW(LoadConfigFile(tmp / "old.yaml", c));
  WriteText(tmp / "other.yaml", "mapping:\n  busy_frames: 7\ntracking:\n  rolling_shutter_refine: false\n");
  const std::string e = ErrorOf([&] { LoadConfigFile(tmp / "other.yaml", c); });
  EXPECT_NE(e.find("other.yaml:2: 'mapping.busy_frames' is no longer a key: a constant, kMappingBusyFrames"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("(its value was 5)"), std::string::npos) << e;
  EXPECT_NE(e.find("'tracking.rolling_shutter_refine' is no longer a key: tracking.refinements.rolling_shutter_refine"),
            std::string::npos)
      << e;
  WriteText(tmp / "warn.yaml", "unknown_keys: warn\nmapping:\n  busy_frames: 7\n");
  EXPECT_NO_THROW(LoadConfigFile(tmp / "warn.yaml", c));
}

TEST(Config, RemovedKeysAreNotKeys) {
  // Every entry names a key this version does not read, and one only once.
  std::set<std::string> keys, removed;
  Config c;
  c.VisitSections([&](const char* section, auto& s) {
    s.Visit([&](const char* key, auto&, const char*) { keys.insert(std::string(section) + "." + key); });
  });
  for (const RemovedConfigKey& r : RemovedConfigKeys()) {
    EXPECT_FALSE(keys.count(r.key)) << r.key;
    EXPECT_TRUE(removed.insert(r.key).second) << r.key << " listed twice";
    EXPECT_TRUE(SameConfigValue(r.last_value, r.last_value)) << r.key;
  }
  EXPECT_TRUE(SameConfigValue("3", "3.0"));
  EXPECT_TRUE(SameConfigValue("True", "true"));
  EXPECT_FALSE(SameConfigValue("0.3", "0.31"));
  EXPECT_FALSE(SameConfigValue("false", "true"));
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
  c.dataset.max_time_difference = 0;
  const std::string e = ErrorOf([&] { c.Validate("my.yaml"); });
  EXPECT_NE(e.find("my.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("camera.fx = -1: must be > 0"), std::string::npos) << e;
  EXPECT_NE(e.find("camera.fps = 0"), std::string::npos) << e;
  EXPECT_NE(e.find("dataset.max_time_difference = 0"), std::string::npos) << e;
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
  a.dataset.max_time_difference = 0.05;
  a.tracking.refinements.trusted_points = false;  // a sub-section
  TempDir tmp;
  WriteText(tmp / "a.yaml", ConfigToYaml(a));
  Config b;
  LoadConfigFile(tmp / "a.yaml", b);
  EXPECT_EQ(ConfigToYaml(a), ConfigToYaml(b));
  EXPECT_DOUBLE_EQ(b.camera.fx, a.camera.fx);
  EXPECT_FALSE(b.tracking.refinements.trusted_points);
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
