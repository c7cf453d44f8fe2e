// The Yolo-Fastest models ship in models/; the photo tests need
// /usr/share/darknet/data/person.jpg (Debian package darknet).
#include "sgslam/detection/dnn_detector.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <optional>

#include "sgslam/common/error.h"
#include "sgslam/detection/darknet_model.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;

const fs::path kPhoto = "/usr/share/darknet/data/person.jpg";

// The models in the source tree (the build tree's copy is what DefaultModelDir finds).
const fs::path kModelDir = test::SourceDir() / "models" / kDefaultModelFolder;

// Sets an environment variable for the scope, or unsets it (nullopt).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, std::optional<std::string> value) : name_(name) {
    if (const char* old = std::getenv(name)) saved_ = old;
    if (value) {
      setenv(name, value->c_str(), 1);
    } else {
      unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (saved_) {
      setenv(name_, saved_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }

 private:
  const char* name_;
  std::optional<std::string> saved_;
};

#define REQUIRE_PHOTO(var)                                                                                          \
  if (!fs::exists(kPhoto)) GTEST_SKIP() << kPhoto << " not found: apt-get install --no-install-recommends darknet"; \
  const cv::Mat var = cv::imread(kPhoto.string());                                                                  \
  ASSERT_FALSE(var.empty())

DetectorConfig ConfigFor(const fs::path& dir, const std::string& model = "yolo-fastest-1.1") {
  DetectorConfig c;
  c.model_dir = dir.string();
  c.model = model;
  return c;
}

// Expects an InputError whose message contains `needle`.
template <class F>
void ExpectInputErrorNaming(F&& make, const std::string& needle) {
  try {
    make();
    ADD_FAILURE() << "no InputError; expected one naming " << needle;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

void ExpectPersonAsInPhoto(const std::vector<Detection>& detections) {
  // person.jpg (640x424): a man stands at x ~ 190..280, y ~ 95..380 beside a horse and a dog.
  const Detection* person = nullptr;
  for (const auto& d : detections) {
    if (d.class_id == 0 && (!person || d.score > person->score)) person = &d;
  }
  ASSERT_NE(person, nullptr) << "no person found";
  EXPECT_EQ(person->class_name, "person");
  EXPECT_GT(person->score, 0.5f);
  const cv::Point2f c = (person->box.tl() + person->box.br()) * 0.5f;
  EXPECT_NEAR(c.x, 230, 40);
  EXPECT_NEAR(c.y, 235, 50);
  EXPECT_NEAR(person->box.height, 280, 70);
  EXPECT_NEAR(person->box.width, 95, 45);
  for (const auto& d : detections) {
    EXPECT_GE(d.box.x, 0.f);
    EXPECT_GE(d.box.y, 0.f);
    EXPECT_LE(d.box.x + d.box.width, 640.f + 1e-3f);
    EXPECT_LE(d.box.y + d.box.height, 424.f + 1e-3f);
  }
}

TEST(DnnDetector, FindsThePersonInARealPhoto) {
  const fs::path& dir = kModelDir;
  REQUIRE_PHOTO(photo);
  for (const char* model : {"yolo-fastest-1.1", "yolo-fastest-1.1-xl"}) {
    SCOPED_TRACE(model);
    DnnDetector detector(ConfigFor(dir, model));
    const auto detections = detector.Detect(photo, 0);
    ExpectPersonAsInPhoto(detections);
    const auto again = detector.Detect(photo, 0);  // deterministic
    ASSERT_EQ(again.size(), detections.size());
    for (std::size_t i = 0; i < again.size(); ++i) EXPECT_EQ(again[i].box, detections[i].box);
    EXPECT_NE(detector.Describe().find(model), std::string::npos);
  }
}

// OpenCV's [yolo] layer drops class scores <= 0.2 unless the cfg says otherwise.
TEST(DnnDetector, KeepsScoresBelowTheLayerDefault) {
  const fs::path& dir = kModelDir;
  REQUIRE_PHOTO(photo);
  auto config = ConfigFor(dir);
  config.score_threshold = config.person_score_threshold = 0.05;
  DnnDetector detector(config);
  const auto detections = detector.Detect(photo, 0);
  bool low = false;
  for (const auto& d : detections) {
    EXPECT_GE(d.score, 0.05f);
    low = low || d.score < 0.2f;
  }
  EXPECT_TRUE(low) << "no detection scored in [0.05, 0.2)";
}

TEST(DnnDetector, MissingOrBrokenFilesAreNamed) {
  const fs::path& dir = kModelDir;
  test::TempDir tmp;
  ExpectInputErrorNaming([&] { DnnDetector d(ConfigFor(tmp / "absent")); }, (tmp / "absent").string());
  ExpectInputErrorNaming([&] { DnnDetector d(ConfigFor(tmp.path())); }, (tmp / "yolo-fastest-1.1.cfg").string());
  for (const char* f : {"yolo-fastest-1.1.cfg", "yolo-fastest-1.1.weights", "coco.names", "yolo-fastest-1.1-xl.cfg"}) {
    fs::copy_file(dir / f, tmp / f);
  }
  // Garbage weights: OpenCV rejects them.
  test::WriteText(tmp / "yolo-fastest-1.1.weights", "garbage garbage garbage garbage");
  ExpectInputErrorNaming([&] { DnnDetector d(ConfigFor(tmp.path())); }, (tmp / "yolo-fastest-1.1.weights").string());
  // Truncated weights, and another model's weights: OpenCV accepts both, the size check does not.
  const auto weights_size = fs::file_size(dir / "yolo-fastest-1.1.weights");
  fs::copy_file(dir / "yolo-fastest-1.1.weights", tmp / "yolo-fastest-1.1.weights",
                fs::copy_options::overwrite_existing);
  fs::resize_file(tmp / "yolo-fastest-1.1.weights", weights_size / 2);
  ExpectInputErrorNaming([&] { DnnDetector d(ConfigFor(tmp.path())); }, (tmp / "yolo-fastest-1.1.weights").string());
  fs::copy_file(dir / "yolo-fastest-1.1.weights", tmp / "yolo-fastest-1.1-xl.weights");
  ExpectInputErrorNaming([&] { DnnDetector d(ConfigFor(tmp.path(), "yolo-fastest-1.1-xl")); },
                         (tmp / "yolo-fastest-1.1-xl.weights").string());
  // Garbage cfg.
  fs::copy_file(dir / "yolo-fastest-1.1.weights", tmp / "yolo-fastest-1.1.weights",
                fs::copy_options::overwrite_existing);
  test::WriteText(tmp / "yolo-fastest-1.1.cfg", "\x01\x02 this is no cfg\n[[[\n");
  ExpectInputErrorNaming([&] { DnnDetector d(ConfigFor(tmp.path())); }, (tmp / "yolo-fastest-1.1.cfg").string());
  // A cfg OpenCV cannot parse although it looks like one.
  test::WriteText(tmp / "yolo-fastest-1.1.cfg", "[net]\nwidth=320\n[frobnicate]\nsize=3\n[yolo]\nclasses=80\n");
  ExpectInputErrorNaming([&] { DnnDetector d(ConfigFor(tmp.path())); }, (tmp / "yolo-fastest-1.1.cfg").string());
  // A names file that does not fit the cfg.
  fs::copy_file(dir / "yolo-fastest-1.1.cfg", tmp / "yolo-fastest-1.1.cfg", fs::copy_options::overwrite_existing);
  test::WriteText(tmp / "coco.names", "person\ncar\n");
  ExpectInputErrorNaming([&] { DnnDetector d(ConfigFor(tmp.path())); }, (tmp / "coco.names").string());
}

// With no folder configured and no $SGSLAM_MODEL_DIR, the models that ship with
// sgslam are used, found beside the executable (here build/share/sgslam).
TEST(DnnDetector, DefaultsToTheShippedModels) {
  ScopedEnv no_env("SGSLAM_MODEL_DIR", std::nullopt);
  const fs::path dir = ResolveModelDir("");
  EXPECT_EQ(dir, DefaultModelDir());
  EXPECT_EQ(dir.filename(), kDefaultModelFolder);
  EXPECT_EQ(dir.parent_path().parent_path().filename(), "sgslam") << dir;  // <...>/share/sgslam/models/<folder>
  DnnDetector detector{DetectorConfig{}};
  EXPECT_NE(detector.Describe().find((dir / "yolo-fastest-1.1.cfg").string()), std::string::npos)
      << detector.Describe();
}

TEST(DnnDetector, EnvironmentAndConfigComeBeforeTheDefault) {
  test::TempDir tmp;
  {
    ScopedEnv env("SGSLAM_MODEL_DIR", tmp.path().string());
    EXPECT_EQ(ResolveModelDir(""), tmp.path());
    EXPECT_EQ(ResolveModelDir(kModelDir.string()), kModelDir);
  }
  ScopedEnv env("SGSLAM_MODEL_DIR", (tmp / "absent").string());
  ExpectInputErrorNaming([&] { ResolveModelDir(""); }, "SGSLAM_MODEL_DIR");
  ExpectInputErrorNaming([&] { ResolveModelDir(""); }, (tmp / "absent").string());
}

// A folder with a SHA256SUMS list refuses a file that does not match it.
TEST(DnnDetector, ChecksumMismatchNamesTheFile) {
  const fs::path& dir = kModelDir;
  test::TempDir tmp;
  for (const char* f : {"yolo-fastest-1.1.cfg", "yolo-fastest-1.1.weights", "coco.names", "SHA256SUMS"}) {
    fs::copy_file(dir / f, tmp / f);
  }
  { DnnDetector intact(ConfigFor(tmp.path())); }
  // One weight changed: the size check cannot see it, the checksum does.
  {
    std::fstream weights(tmp / "yolo-fastest-1.1.weights", std::ios::in | std::ios::out | std::ios::binary);
    weights.seekp(1000);
    weights.put('\x7f');
  }
  ExpectInputErrorNaming([&] { DnnDetector d(ConfigFor(tmp.path())); }, (tmp / "yolo-fastest-1.1.weights").string());
  ExpectInputErrorNaming([&] { DnnDetector d(ConfigFor(tmp.path())); }, "checksum");
  fs::copy_file(dir / "yolo-fastest-1.1.weights", tmp / "yolo-fastest-1.1.weights", fs::copy_options::overwrite_existing);
  test::WriteText(tmp / "coco.names", "person\n");
  ExpectInputErrorNaming([&] { DnnDetector d(ConfigFor(tmp.path())); }, (tmp / "coco.names").string());
  // A malformed list is an error naming its line.
  fs::copy_file(dir / "coco.names", tmp / "coco.names", fs::copy_options::overwrite_existing);
  test::WriteText(tmp / "SHA256SUMS", "not a checksum line\n");
  ExpectInputErrorNaming([&] { DnnDetector d(ConfigFor(tmp.path())); }, (tmp / "SHA256SUMS").string() + ":1");
  // Without a list the files are loaded unchecked (a user's own model).
  fs::remove(tmp / "SHA256SUMS");
  { DnnDetector unchecked(ConfigFor(tmp.path())); }
}

}  // namespace
}  // namespace sgslam
