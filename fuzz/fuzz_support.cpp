#include "fuzz_support.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <system_error>
#include <utility>

namespace sgslam::fuzz {

namespace fs = std::filesystem;

namespace {

bool g_accepted = false;
std::string g_refusal;

// $TMPDIR, else memory (/dev/shm) where there is some: on a disk, rewriting the
// same files thousands of times a second waits for the disk (ext4 flushes a file
// truncated and written again).
std::string Base() {
  if (const char* tmp = std::getenv("TMPDIR"); tmp && *tmp) return tmp;
  return access("/dev/shm", W_OK | X_OK) == 0 ? "/dev/shm" : "/tmp";
}

class Scratch {
 public:
  Scratch() {
    spdlog::set_level(spdlog::level::off);  // the parsers' warnings (an unknown key ignored) would flood the log
    std::string pattern = Base() + "/sgslam-fuzz-XXXXXX";
    if (!mkdtemp(pattern.data())) {
      std::perror(("cannot create a scratch folder " + pattern).c_str());
      std::abort();
    }
    path_ = pattern;
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

}  // namespace

const fs::path& ScratchDir() {
  static const Scratch scratch;
  return scratch.path();
}

fs::path WriteScratch(const std::string& name, std::string_view bytes) {
  const fs::path path = ScratchDir() / name;
  std::error_code ec;
  fs::remove(path, ec);  // a new file, not one truncated (see Base)
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out.flush()) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path;
}

void RemoveScratch(const std::string& name) {
  std::error_code ec;
  fs::remove(ScratchDir() / name, ec);
}

bool LastInputAccepted() { return g_accepted; }
void SetLastInputAccepted(bool accepted) { g_accepted = accepted; }
const std::string& LastRefusal() { return g_refusal; }
void SetLastRefusal(std::string message) { g_refusal = std::move(message); }

void Broken(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "%s:%d: the parser's result breaks its promise: %s\n", file, line, condition);
  std::abort();
}

}  // namespace sgslam::fuzz
