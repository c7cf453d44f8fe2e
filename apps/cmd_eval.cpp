#include <CLI/CLI.hpp>

#include "commands.h"
#include "sgslam/common/error.h"

namespace sgslam::app {

Action AddEvalCommand(CLI::App& root) {
  root.add_subcommand("eval", "(not yet implemented)");
  return [] () -> int { throw Error("'eval' is not implemented yet"); };
}

}  // namespace sgslam::app
