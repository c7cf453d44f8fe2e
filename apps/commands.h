// The sgslam subcommands. Each Add*Command registers its options on the root app
// and returns the action main() runs when that subcommand was chosen. An action
// returns the process exit status; errors the user can fix are thrown as
// sgslam::Error and reported by main() with exit status 1.
#pragma once

#include <functional>

namespace CLI {
class App;
}

namespace sgslam::app {

using Action = std::function<int()>;

Action AddRunCommand(CLI::App& root);
Action AddEvalCommand(CLI::App& root);
Action AddSynthCommand(CLI::App& root);
Action AddDemoCommand(CLI::App& root);
Action AddConfigCommand(CLI::App& root);
Action AddVocabCommand(CLI::App& root);
Action AddMapCommand(CLI::App& root);
Action AddViewCommand(CLI::App& root);

// Exit statuses shared by every subcommand.
constexpr int kExitOk = 0;
constexpr int kExitError = 1;  // bad input, bad config, I/O failure
constexpr int kExitUsage = 2;  // bad command line

}  // namespace sgslam::app
