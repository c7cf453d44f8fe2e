#include "support/test_support.h"

#include <sys/wait.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <stdexcept>

namespace sgslam::test {

namespace fs = std::filesystem;

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  std::random_device rd;
  const fs::path base = fs::temp_directory_path();
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path p = base / ("sgslam-test-" + std::to_string(rd()) + "-" + std::to_string(counter++));
    if (fs::create_directory(p)) {
      path_ = p;
      return;
    }
  }
  throw std::runtime_error("cannot create a temporary folder under " + base.string());
}

TempDir::~TempDir() {
  std::error_code ec;
  if (!std::getenv("SGSLAM_KEEP_TEST_FILES")) fs::remove_all(path_, ec);
}

std::optional<fs::path> SharedPath(const std::string& sub) {
  fs::path root;
  if (const char* env = std::getenv("SGSLAM_SHARED_DIR"); env && *env) {
    root = env;
  } else {
    root = fs::path(SGSLAM_SOURCE_DIR) / ".." / "shared";
  }
  const fs::path p = root / sub;
  std::error_code ec;
  if (!fs::exists(p, ec)) return std::nullopt;
  return fs::canonical(p, ec);
}

fs::path SourceDir() { return SGSLAM_SOURCE_DIR; }

static std::string Quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += "'\\''";
    else out += c;
  }
  return out + "'";
}

std::string ShellQuote(const std::string& s) { return Quote(s); }

CommandResult RunSgslam(const std::vector<std::string>& args) {
  std::string cmd = Quote(SGSLAM_BINARY);
  for (const auto& a : args) cmd += " " + Quote(a);
  return RunShell(cmd);
}

CommandResult RunShell(std::string cmd) {
  cmd += " 2>&1 </dev/null";
  CommandResult result;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) throw std::runtime_error("popen failed for: " + cmd);
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) result.output.append(buf.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

void WriteText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace sgslam::test
