// The dataset folder's sgslam.yaml as a file (issue #47): a FIFO or a folder under
// that name is an error naming it (it was taken for no file), and a key it repeats
// is an error whether or not --config is given.
#include <gtest/gtest.h>

#include "sgslam/common/error.h"
#include "sgslam/system/run_config.h"
#include "support/reader_faults.h"
#include "support/test_support.h"
#include "support/tiny_dataset.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::ExpectAll;
using test::RefusalOf;
using test::TempDir;

TEST(DatasetConfigFile, AFifoOrAFolderIsAnErrorNotAbsent) {
  const TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 1);
  fs::remove(tmp / "seq" / "sgslam.yaml");
  test::MakeFifo(tmp / "seq" / "sgslam.yaml");
  ExpectAll(RefusalOf<Error>([&] { ResolveRunConfig(std::nullopt, tmp / "seq"); }, 10, tmp / "seq" / "sgslam.yaml"),
            {"sgslam.yaml", "FIFO"});
  test::WriteText(tmp / "orb.yaml", "orb:\n  features: 900\n");
  ExpectAll(RefusalOf<Error>([&] { ResolveRunConfig(tmp / "orb.yaml", tmp / "seq"); }, 10, tmp / "seq" / "sgslam.yaml"),
            {"sgslam.yaml", "FIFO"});
  fs::remove(tmp / "seq" / "sgslam.yaml");
  fs::create_directory(tmp / "seq" / "sgslam.yaml");
  ExpectAll(RefusalOf<Error>([&] { ResolveRunConfig(std::nullopt, tmp / "seq"); }), {"sgslam.yaml", "folder"});
}

TEST(DatasetConfigFile, ARepeatedKeyIsAnErrorWithOrWithoutConfig) {
  const TempDir tmp;
  test::WriteTinyDataset(tmp / "seq", 1);
  test::WriteText(tmp / "seq" / "sgslam.yaml", "camera:\n  width: 64\n  height: 48\ncamera:\n  fx: 50\n");
  ExpectAll(RefusalOf<ConfigError>([&] { ResolveRunConfig(std::nullopt, tmp / "seq"); }),
            {"sgslam.yaml:4", "'camera' given twice, at lines 1 and 4"});
  test::WriteText(tmp / "orb.yaml", "orb:\n  features: 900\n");
  ExpectAll(RefusalOf<ConfigError>([&] { ResolveRunConfig(tmp / "orb.yaml", tmp / "seq"); }),
            {"sgslam.yaml:4", "lines 1 and 4"});
}

}  // namespace
}  // namespace sgslam
