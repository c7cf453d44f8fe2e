#include <CLI/CLI.hpp>

#include "commands.h"
#include "sgslam/common/error.h"

namespace sgslam::app {

Action AddDemoCommand(CLI::App& root) {
  root.add_subcommand("demo", "(not yet implemented)");
  return [] () -> int { throw Error("'demo' is not implemented yet"); };
}

}  // namespace sgslam::app
