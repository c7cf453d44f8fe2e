#include <CLI/CLI.hpp>

#include "commands.h"
#include "sgslam/common/error.h"

namespace sgslam::app {

Action AddSynthCommand(CLI::App& root) {
  root.add_subcommand("synth", "(not yet implemented)");
  return [] () -> int { throw Error("'synth' is not implemented yet"); };
}

}  // namespace sgslam::app
