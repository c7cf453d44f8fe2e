#include <CLI/CLI.hpp>

#include "commands.h"
#include "sgslam/common/error.h"

namespace sgslam::app {

Action AddRunCommand(CLI::App& root) {
  root.add_subcommand("run", "(not yet implemented)");
  return [] () -> int { throw Error("'run' is not implemented yet"); };
}

}  // namespace sgslam::app
