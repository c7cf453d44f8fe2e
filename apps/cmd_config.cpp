// `sgslam config`: the configuration a run would use, or the reference of every key.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>
#include <string>

#include "commands.h"
#include "sgslam/config/reference.h"
#include "sgslam/config/yaml_io.h"
#include "sgslam/system/run_config.h"

namespace sgslam::app {

namespace {

struct ConfigArgs {
  std::string dataset, config;
  bool reference = false;
};

int RunConfigCommand(const ConfigArgs& a) {
  if (a.reference) {
    std::fputs(ConfigReferenceMarkdown().c_str(), stdout);
    return kExitOk;
  }
  Config config;
  std::string source = "defaults";
  if (!a.dataset.empty() || !a.config.empty()) {
    const RunConfig rc = ResolveRunConfig(a.config.empty() ? std::nullopt : std::optional<std::filesystem::path>(a.config),
                                          a.dataset.empty() ? std::filesystem::path(".") : std::filesystem::path(a.dataset));
    config = rc.config;
    source = rc.source;
  }
  std::fputs(("# configuration (source: " + source + ")\n" + ConfigToYaml(config)).c_str(), stdout);
  return kExitOk;
}

}  // namespace

Action AddConfigCommand(CLI::App& root) {
  auto args = std::make_shared<ConfigArgs>();
  CLI::App* cmd = root.add_subcommand(
      "config", "Print the configuration a run would use (default: the defaults), or --reference every key");
  cmd->add_option("--dataset", args->dataset, "Dataset folder, as for run (its sgslam.yaml or camera preset)");
  cmd->add_option("--config", args->config, "YAML config file or shipped config name, as for run");
  cmd->add_flag("--reference", args->reference, "Markdown reference of every key (docs/configuration.md)");
  return [args] { return RunConfigCommand(*args); };
}

}  // namespace sgslam::app
