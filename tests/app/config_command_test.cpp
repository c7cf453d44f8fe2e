// `sgslam config`: the reference in docs/configuration.md is what the code says
// (regenerate it when a key changes), and the printed configuration loads back.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "sgslam/config/config.h"
#include "sgslam/config/yaml_io.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

TEST(ConfigCommand, TheReferenceInDocsIsUpToDate) {
  const auto r = test::RunSgslam({"config", "--reference"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream file(test::SourceDir() / "docs" / "configuration.md");
  std::stringstream docs;
  docs << file.rdbuf();
  EXPECT_EQ(docs.str(), r.output)
      << "docs/configuration.md is stale: run `build/sgslam config --reference > docs/configuration.md`";
}

TEST(ConfigCommand, PrintsAConfigurationThatLoadsBack) {
  test::TempDir tmp;
  test::WriteText(tmp / "mine.yaml", "orb:\n  features: 1234\n");
  const auto r = test::RunSgslam({"config", "--config", (tmp / "mine.yaml").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("features: 1234"), std::string::npos) << r.output;
  test::WriteText(tmp / "printed.yaml", r.output);
  Config c;
  LoadConfigFile(tmp / "printed.yaml", c);  // every key it prints is known
  EXPECT_EQ(c.orb.features, 1234);
}

}  // namespace
}  // namespace sgslam
