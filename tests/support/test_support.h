// Helpers shared by the tests: scratch folders, the shared data folder, and running
// the sgslam binary the way a user would.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace sgslam::test {

// A fresh folder under the system temp dir, removed with everything in it on scope exit.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// ../shared (or $SGSLAM_SHARED_DIR) / sub, when it exists.
std::optional<std::filesystem::path> SharedPath(const std::string& sub);

// The source tree (for configs/).
std::filesystem::path SourceDir();

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};
// Runs the built sgslam binary with the arguments (shell-quoted here).
CommandResult RunSgslam(const std::vector<std::string>& args);
// Runs a shell command line (sh -c), stdin from /dev/null.
CommandResult RunShell(std::string command);
// s in single quotes for sh.
std::string ShellQuote(const std::string& s);

void WriteText(const std::filesystem::path& path, const std::string& text);

}  // namespace sgslam::test

// Skips the current test with a clear message when a shared data folder is absent.
#define SGSLAM_REQUIRE_SHARED(var, sub)                                                          \
  const auto var##_opt = ::sgslam::test::SharedPath(sub);                                        \
  if (!var##_opt) GTEST_SKIP() << "shared data '" << (sub) << "' not found (set SGSLAM_SHARED_DIR)"; \
  const std::filesystem::path var = *var##_opt
