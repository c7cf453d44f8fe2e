#include "support/shared_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "sgslam/synth/depth_noise.h"

namespace sgslam::test {

namespace fs = std::filesystem;

namespace {

// A file descriptor, closed (and with it its lock released) at scope exit.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }
  int release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
  }

 private:
  int fd_;
};

[[noreturn]] void Fail(const std::string& what, const fs::path& path) {
  throw std::runtime_error(what + " " + path.string() + ": " + std::strerror(errno));
}

void Lock(int fd, int operation, const fs::path& path) {
  while (::flock(fd, operation) != 0) {
    if (errno != EINTR) Fail("cannot lock", path);
  }
}

// The running test program's file name, and a stamp that changes when it is rebuilt.
struct Program {
  std::string name, stamp;
};

Program ThisProgram() {
  std::string name = fs::read_symlink("/proc/self/exe").filename().string();
  const std::string deleted = " (deleted)";  // rebuilt while it runs: still the file it runs
  if (name.ends_with(deleted)) name.resize(name.size() - deleted.size());
  struct stat st {};
  if (::stat("/proc/self/exe", &st) != 0) Fail("cannot stat", "/proc/self/exe");
  char stamp[64];
  std::snprintf(stamp, sizeof stamp, "%llx-%llx-%llx", static_cast<unsigned long long>(st.st_size),
                static_cast<unsigned long long>(st.st_mtim.tv_sec), static_cast<unsigned long long>(st.st_mtim.tv_nsec));
  return {name, stamp};
}

// folder opened with a shared lock on it, or -1 when it does not exist (or was
// removed while this process waited for the lock).
int OpenShared(const fs::path& folder) {
  Fd fd(::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (fd.get() < 0) {
    if (errno == ENOENT) return -1;
    Fail("cannot open", folder);
  }
  Lock(fd.get(), LOCK_SH, folder);
  struct stat held {}, now {};
  if (::fstat(fd.get(), &held) != 0) Fail("cannot stat", folder);
  if (::stat(folder.c_str(), &now) != 0 || now.st_ino != held.st_ino || now.st_dev != held.st_dev) return -1;
  return fd.release();
}

// Under root's make lock: removes every folder that is not of this build (other
// builds' folders no process holds, and what an interrupted make or removal left).
void RemoveUnused(const fs::path& root, const std::string& stamp) {
  std::vector<fs::path> others;
  for (const auto& entry : fs::directory_iterator(root)) {
    if (entry.is_directory() && !entry.path().filename().string().ends_with("." + stamp)) others.push_back(entry.path());
  }
  for (std::size_t i = 0; i < others.size(); ++i) {
    Fd fd(::open(others[i].c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (fd.get() < 0 || ::flock(fd.get(), LOCK_EX | LOCK_NB) != 0) continue;  // gone, or in use
    // Out of the way first: a process that opens it by name afterwards finds nothing.
    const fs::path doomed = root / (".removing." + std::to_string(::getpid()) + "." + std::to_string(i));
    std::error_code ec;
    fs::rename(others[i], doomed, ec);
    if (!ec) fs::remove_all(doomed, ec);
  }
}

}  // namespace

fs::path SharedFolder(const std::string& name, const std::function<void(const fs::path&)>& make) {
  static std::mutex mutex;
  static std::map<std::string, fs::path> known;  // this process's, each held by a shared lock until it exits
  std::lock_guard guard(mutex);
  if (const auto it = known.find(name); it != known.end()) return it->second;
  static const Program program = ThisProgram();
  const fs::path root = fs::path(SGSLAM_BUILD_DIR) / "tests" / "shared" / program.name;
  const fs::path folder = root / (name + "." + program.stamp);
  fs::create_directories(root);
  for (;;) {
    if (const int fd = OpenShared(folder); fd >= 0) {
      known[name] = folder;
      return folder;  // fd stays open: the shared lock keeps the folder from removal
    }
    const fs::path lock_path = root / ".lock";
    Fd lock(::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644));
    if (lock.get() < 0) Fail("cannot open", lock_path);
    Lock(lock.get(), LOCK_EX, lock_path);
    if (fs::exists(folder)) continue;  // another process made it meanwhile
    RemoveUnused(root, program.stamp);
    const fs::path partial = root / (name + "." + program.stamp + ".partial");
    fs::create_directories(partial);
    try {
      make(partial);
    } catch (...) {
      std::error_code ec;
      fs::remove_all(partial, ec);
      throw;
    }
    fs::rename(partial, folder);
  }
}

fs::path SharedSequence(const synth::SynthOptions& o) {
  std::string name = o.preset + "-seed" + std::to_string(o.seed);
  if (o.frames) name += "-" + std::to_string(*o.frames) + "frames";
  if (o.readout) {
    char readout[32];
    std::snprintf(readout, sizeof readout, "-readout%g", *o.readout);
    name += readout;
  }
  if (o.depth_noise) name += std::string("-") + synth::DepthNoiseName(*o.depth_noise);
  return SharedFolder(name, [&](const fs::path& dir) { synth::GenerateSequence(o, dir); });
}

}  // namespace sgslam::test
