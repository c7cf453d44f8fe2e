// Which configuration a run uses: --config, the folder's sgslam.yaml, the camera
// preset of the folder name, and how they combine.
#include "sgslam/system/run_config.h"

#include <gtest/gtest.h>

#include "sgslam/camera/presets.h"
#include "sgslam/common/error.h"
#include "sgslam/synth/writer.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;

TEST(RunConfig, AFolderOfAKnownCameraGetsItsPreset) {
  test::TempDir tmp;
  const fs::path dir = tmp / "rgbd_dataset_freiburg1_rpy";
  fs::create_directories(dir);
  const RunConfig rc = ResolveRunConfig(std::nullopt, dir);
  EXPECT_DOUBLE_EQ(rc.config.camera.readout, CameraPreset("tum_fr1")->readout);
  EXPECT_DOUBLE_EQ(rc.config.camera.readout, 0.03);
}

TEST(RunConfig, AnUnknownFolderGetsTheTumFr1Camera) {
  test::TempDir tmp;
  const RunConfig rc = ResolveRunConfig(std::nullopt, tmp.path());
  EXPECT_DOUBLE_EQ(rc.config.camera.fx, CameraPreset("tum_fr1")->fx);
  EXPECT_DOUBLE_EQ(rc.config.camera.readout, 0.03);
}

TEST(RunConfig, AConfigWithoutACameraSectionKeepsTheFoldersCamera) {
  test::TempDir tmp;
  const fs::path dir = tmp / "rgbd_dataset_freiburg2_xyz";
  fs::create_directories(dir);
  test::WriteText(tmp / "budget.yaml", "orb:\n  features: 900\n");
  const RunConfig rc = ResolveRunConfig(tmp / "budget.yaml", dir);
  EXPECT_EQ(rc.config.orb.features, 900);
  EXPECT_DOUBLE_EQ(rc.config.camera.fx, CameraPreset("tum_fr2")->fx);
  EXPECT_NE(rc.source.find("tum_fr2"), std::string::npos) << rc.source;

  const RunConfig unknown = ResolveRunConfig(tmp / "budget.yaml", tmp.path());
  EXPECT_DOUBLE_EQ(unknown.config.camera.readout, 0.03) << "the TUM fr1 camera, readout included";
}

// A synthetic sequence (or any folder with its own sgslam.yaml) keeps its camera
// and its settings under a --config that has no camera section: an ORB budget for
// a panel must not put the TUM fr1 calibration on a synthetic camera.
TEST(RunConfig, AConfigWithoutACameraSectionGoesOnTopOfTheFoldersOwnFile) {
  test::TempDir tmp;
  const fs::path dir = tmp / "synthetic";
  fs::create_directories(dir);
  test::WriteText(dir / "sgslam.yaml", synth::CameraYaml(0.02));
  test::WriteText(tmp / "budget.yaml", "orb:\n  features: 900\n");
  const RunConfig rc = ResolveRunConfig(tmp / "budget.yaml", dir);
  EXPECT_EQ(rc.config.orb.features, 900);
  EXPECT_DOUBLE_EQ(rc.config.camera.fx, 525.0) << "the synthetic camera, not TUM fr1's";
  EXPECT_DOUBLE_EQ(rc.config.camera.k1, 0.0);
  EXPECT_DOUBLE_EQ(rc.config.camera.readout, 0.02);
  EXPECT_EQ(rc.config.detector.backend, "file") << "the folder's other settings stay too";
  EXPECT_NE(rc.source.find("budget.yaml over"), std::string::npos) << rc.source;

  test::WriteText(tmp / "detector.yaml", "detector:\n  backend: dnn\n");
  EXPECT_EQ(ResolveRunConfig(tmp / "detector.yaml", dir).config.detector.backend, "dnn") << "the given file wins";
}

TEST(RunConfig, AConfigWithACameraSectionDescribesTheCamera) {
  test::TempDir tmp;
  const fs::path dir = tmp / "rgbd_dataset_freiburg1_desk";
  fs::create_directories(dir);
  test::WriteText(tmp / "cam.yaml", "camera:\n  fx: 600.0\n");
  const RunConfig rc = ResolveRunConfig(tmp / "cam.yaml", dir);
  EXPECT_DOUBLE_EQ(rc.config.camera.fx, 600.0);
  EXPECT_DOUBLE_EQ(rc.config.camera.readout, 0.0) << "a readout the file does not give is a global shutter";

  // Synthetic sequences carry their (global-shutter) camera.
  test::WriteText(dir / "sgslam.yaml", synth::CameraYaml());
  EXPECT_DOUBLE_EQ(ResolveRunConfig(std::nullopt, dir).config.camera.readout, 0.0);
}

TEST(RunConfig, TheShippedTumFr1ConfigMatchesThePreset) {
  const RunConfig rc = ResolveRunConfig(test::SourceDir() / "configs" / "tum_fr1.yaml", "/nonexistent/x");
  EXPECT_DOUBLE_EQ(rc.config.camera.readout, CameraPreset("tum_fr1")->readout);
  EXPECT_DOUBLE_EQ(rc.config.camera.fx, CameraPreset("tum_fr1")->fx);
}

// --config NAME: the configs that ship with sgslam, found beside the executable
// (the test's own: build/tests -> build/share/sgslam), when NAME is no file here.
TEST(RunConfig, AShippedConfigIsFoundByName) {
  for (const char* name : {"bonn", "tum_fr3.yaml"}) {
    const fs::path path = ResolveConfigPath(name);
    EXPECT_TRUE(fs::is_regular_file(path)) << path;
    EXPECT_EQ(path.parent_path().filename(), "configs") << path;
  }
  test::TempDir tmp;
  const RunConfig rc = ResolveRunConfig(fs::path("bonn"), tmp.path());
  EXPECT_DOUBLE_EQ(rc.config.camera.fx, CameraPreset("bonn")->fx);
  // A file of that name in the working directory or a path is taken as it is.
  EXPECT_EQ(ResolveConfigPath(tmp / "bonn"), tmp / "bonn");
  try {
    ResolveConfigPath("tum_fr9");
    ADD_FAILURE() << "no error for an unknown config name";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("tum_fr9"), std::string::npos) << what;
    EXPECT_NE(what.find("bonn"), std::string::npos) << "lists the shipped names: " << what;
  }
}

// --config naming a folder: an error naming it (the YAML reader's stream error,
// "basic_filebuf::underflow ... Is a directory", named nothing); a bare name that
// is a folder here still finds the shipped config of that name.
TEST(RunConfig, AFolderGivenAsConfigIsAnErrorNamingIt) {
  test::TempDir tmp;
  fs::create_directories(tmp / "conf.yaml");
  try {
    ResolveRunConfig(tmp / "conf.yaml", tmp.path());
    ADD_FAILURE() << "no error for a folder";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("conf.yaml is a folder"), std::string::npos) << e.what();
  }
  const fs::path cwd = fs::current_path();
  fs::create_directories(tmp / "bonn");
  fs::current_path(tmp.path());
  const fs::path shipped = ResolveConfigPath("bonn");
  fs::current_path(cwd);
  EXPECT_EQ(shipped.parent_path().filename(), "configs") << shipped;
}

}  // namespace
}  // namespace sgslam
