// The config file as a file (issue #47): a key given twice at any depth is an
// error naming both lines (yaml-cpp silently kept the first, PyYAML the last), and
// a config that is not a regular file is refused without blocking.
#include <gtest/gtest.h>

#include "sgslam/common/error.h"
#include "sgslam/config/yaml_io.h"
#include "support/reader_faults.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

using test::ExpectAll;
using test::RefusalOf;
using test::TempDir;

std::optional<std::string> LoadRefusal(const std::filesystem::path& file) {
  return RefusalOf<ConfigError>([&] {
    Config c;
    LoadConfigFile(file, c);
  });
}

TEST(ConfigFile, ADuplicatedKeyNamesBothLines) {
  const TempDir tmp;
  test::WriteText(tmp / "c.yaml", "orb:\n  features: 900\n  levels: 4\n  features: 1200\n");
  ExpectAll(LoadRefusal(tmp / "c.yaml"), {"c.yaml:4: ", "'orb.features' given twice, at lines 2 and 4"});
}

TEST(ConfigFile, ADuplicatedTopLevelSectionNamesBothLines) {
  const TempDir tmp;
  // yaml-cpp dropped the second orb section whole: the edit of a copied config.
  test::WriteText(tmp / "c.yaml", "orb:\n  features: 900\ndynamic:\n  mode: sg\norb:\n  levels: 4\n");
  ExpectAll(LoadRefusal(tmp / "c.yaml"), {"c.yaml:5: ", "'orb' given twice, at lines 1 and 5"});
  EXPECT_THROW(ConfigFileHasSection(tmp / "c.yaml", "camera"), ConfigError);
}

TEST(ConfigFile, DuplicatesAreFoundAtAnyDepthAndInFlowStyle) {
  const TempDir tmp;
  test::WriteText(tmp / "t.yaml", "detector:\n  dynamic_weight:\n    person: 1.0\n    cat: 0.5\n    person: 0.2\n");
  ExpectAll(LoadRefusal(tmp / "t.yaml"), {"t.yaml:5", "'detector.dynamic_weight.person' given twice, at lines 3 and 5"});
  test::WriteText(tmp / "f.yaml", "camera: {fx: 500, fy: 500,\n  fx: 520}\n");
  ExpectAll(LoadRefusal(tmp / "f.yaml"), {"f.yaml:2", "'camera.fx' given twice, at lines 1 and 2"});
  // Unknown sections are checked too: a duplicate there would be misread as well.
  test::WriteText(tmp / "u.yaml", "unknown_keys: warn\nextra:\n  a: 1\n  a: 2\n");
  ExpectAll(LoadRefusal(tmp / "u.yaml"), {"u.yaml:4", "'extra.a' given twice, at lines 3 and 4"});
}

TEST(ConfigFile, AnAliasIsNotADuplicate) {
  const TempDir tmp;
  // The same map reached twice (an anchor and its alias) repeats no key.
  test::WriteText(tmp / "a.yaml", "unknown_keys: warn\nbase: &b {features: 900}\norb: *b\n");
  Config c;
  EXPECT_NO_THROW(LoadConfigFile(tmp / "a.yaml", c));
  EXPECT_EQ(c.orb.features, 900);
  EXPECT_FALSE(ConfigFileHasSection(tmp / "a.yaml", "camera"));
  EXPECT_TRUE(ConfigFileHasSection(tmp / "a.yaml", "orb"));
}

TEST(ConfigFile, AFifoOrADeviceIsRefusedWithoutBlocking) {
  const TempDir tmp;
  test::MakeFifo(tmp / "c.yaml");
  ExpectAll(RefusalOf<ConfigError>(
                [&] {
                  Config c;
                  LoadConfigFile(tmp / "c.yaml", c);
                },
                10, tmp / "c.yaml"),
            {"config file", "c.yaml", "FIFO"});
  ExpectAll(RefusalOf<ConfigError>([&] { ConfigFileHasSection(tmp / "c.yaml", "camera"); }, 10, tmp / "c.yaml"),
            {"c.yaml", "FIFO"});
  ExpectAll(LoadRefusal("/dev/zero"), {"config file /dev/zero", "device"});
}

TEST(ConfigFile, ALargeFileIsRefusedBeforeItIsRead) {
  const TempDir tmp;
  test::MakeSparse(tmp / "big.yaml", 1ull << 31);
  ExpectAll(LoadRefusal(tmp / "big.yaml"), {"big.yaml", "2147483648 bytes", "more than"});
  ExpectAll(LoadRefusal(tmp / "missing.yaml"), {"config file not found: ", "missing.yaml"});
}

}  // namespace
}  // namespace sgslam
