// sgslam: real-time RGB-D SLAM for dynamic scenes (after SG-SLAM).
// This file only dispatches to the subcommands (see commands.h).
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <fcntl.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <map>

#include "commands.h"
#include "sgslam/common/error.h"

namespace {

// A standard stream the caller closed is reopened on /dev/null: otherwise the next
// file opened takes its descriptor, and a log line or the summary would land in an
// output file being written.
void ReopenClosedStandardStreams() {
  for (int fd = 0; fd <= 2; ++fd) {
    if (fcntl(fd, F_GETFD) != -1 || errno != EBADF) continue;
    const int null = open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY);
    if (null >= 0 && null != fd) {
      dup2(null, fd);
      close(null);
    }
  }
}

// Results go to stdout (eval's table or JSON, run's summary): a write that failed
// (a full disk, a closed pipe) is an error, not a success with the result lost.
int CheckStdout(int status) {
  if (std::fflush(stdout) == 0 && !std::ferror(stdout)) return status;
  std::fprintf(stderr, "error: cannot write to standard output: %s\n", std::strerror(errno));
  return status == sgslam::app::kExitOk ? sgslam::app::kExitError : status;
}

int RunCommand(const std::map<const CLI::App*, sgslam::app::Action>& actions, const CLI::App& root) {
  using namespace sgslam::app;
  try {
    for (const CLI::App* sub : root.get_subcommands()) return actions.at(sub)();
  } catch (const sgslam::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: unexpected failure: %s\n", e.what());
    return kExitError;
  }
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sgslam::app;
  ReopenClosedStandardStreams();
  // SIGUSR1 asks a running `sgslam run` for its maps so far; at any other moment
  // (a run starting or ending, another subcommand) it must not end the process.
  std::signal(SIGUSR1, SIG_IGN);
  CLI::App root{"sgslam: real-time RGB-D visual SLAM for dynamic scenes (after SG-SLAM)"};
  root.require_subcommand(0, 1);  // so an unknown word is reported as such
  int verbosity = 0;
  root.add_flag("-v,--verbose", verbosity, "More log output (repeat for debug output)");
  bool quiet = false;
  root.add_flag("-q,--quiet", quiet, "Only warnings and errors");

  std::map<const CLI::App*, Action> actions;
  const auto add = [&](Action a) { actions[root.get_subcommands({}).back()] = std::move(a); };
  add(AddRunCommand(root));
  add(AddEvalCommand(root));
  add(AddSynthCommand(root));
  add(AddDemoCommand(root));
  add(AddConfigCommand(root));
  add(AddVocabCommand(root));
  add(AddMapCommand(root));
  add(AddViewCommand(root));

  try {
    root.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = root.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }
  // stdout carries results (eval --json is parsed by scripts); logs go to stderr.
  spdlog::set_default_logger(spdlog::stderr_color_mt("sgslam"));
  spdlog::set_pattern("[%l] %v");
  spdlog::set_level(quiet ? spdlog::level::warn
                          : verbosity >= 2 ? spdlog::level::trace
                          : verbosity == 1 ? spdlog::level::debug
                                           : spdlog::level::info);
  if (root.get_subcommands().empty()) {
    std::fprintf(stderr, "%s\nerror: a subcommand is required (run, eval, synth, demo, config, vocab or map)\n", root.help().c_str());
    return kExitUsage;
  }
  return CheckStdout(RunCommand(actions, root));
}
