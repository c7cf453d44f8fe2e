// A command-line option naming a server's port that may be given alone: --NAME
// serves on the default port, --NAME=PORT on another (0: any free one). `run
// --viewer`, `run --foxglove`, `view --foxglove`.
#pragma once

#include <memory>
#include <string>

#include <CLI/CLI.hpp>

namespace sgslam::app {

class PortOption {
 public:
  PortOption(CLI::App& cmd, const std::string& name, int default_port, const std::string& description)
      : text_(std::make_shared<std::string>()), default_port_(default_port) {
    option_ = cmd.add_option(name, *text_, description)->expected(0, 1)->check(CLI::Range(0, 65535));
  }
  CLI::Option* option() const { return option_; }
  // After parsing: the port to serve on, or -1 when the option was not given.
  int port() const {
    if (option_->count() == 0) return -1;
    return text_->empty() ? default_port_ : std::stoi(*text_);
  }

 private:
  std::shared_ptr<std::string> text_;  // shared: the action runs after the command's set-up has returned
  int default_port_;
  CLI::Option* option_ = nullptr;
};

}  // namespace sgslam::app
