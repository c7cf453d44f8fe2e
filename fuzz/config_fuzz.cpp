// YAML configuration files (config/yaml_io.h), loaded onto the defaults and
// validated, as `sgslam run --config` does. Every refusal names the file (a key
// given twice names it with both lines, config/yaml_io.h).
#include "fuzz_support.h"
#include "sgslam/config/yaml_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sgslam;
  const auto path = fuzz::WriteScratch("config.yaml", fuzz::Bytes(data, size));
  fuzz::Parse([&] {
    Config config;
    ConfigFileHasSection(path, "camera");
    LoadConfigFile(path, config);
    config.Validate(path.string());
    ConfigToYaml(config);
  });
  FUZZ_CHECK(fuzz::LastInputAccepted() || fuzz::LastRefusal().find(path.string()) != std::string::npos);
  return 0;
}
