// WriteFileAtomically's clearing of the temporary files that killed writers left.
#include "sgslam/io/atomic_write.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <string>
#include <vector>

#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::TempDir;
using test::WriteText;

std::vector<std::string> Names(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// The id of a process that has ended (a child, reaped).
pid_t DeadPid() {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  int status = 0;
  waitpid(child, &status, 0);
  return child;
}

// The temporary name a writer of path with process id pid gives, in this boot and
// PID namespace: TempFilePrefix's with another id.
std::string TempName(const fs::path& path, pid_t pid, const std::string& suffix) {
  std::string prefix = TempFilePrefix(path);
  prefix.erase(prefix.rfind('.', prefix.size() - 2) + 1);  // "<path>.tmp-sgslam.<owner>."
  return fs::path(prefix + std::to_string(pid) + "." + suffix).filename().string();
}

TEST(WriteFileAtomically, TemporaryNamesCarryTheWritersId) {
  const std::string prefix = TempFilePrefix("/x/room.map");
  EXPECT_EQ(prefix.rfind("/x/room.map.tmp-sgslam.", 0), 0u) << prefix;
  EXPECT_NE(prefix.find("." + std::to_string(getpid()) + "."), std::string::npos) << prefix;
}

TEST(WriteFileAtomically, RemovesTheTemporaryFilesOfDeadWriters) {
  const TempDir tmp;
  const pid_t dead = DeadPid();
  for (const char* suffix : {"0", "aB3xY9", "k2_x9abc"}) {  // linked, mkostemp's, Python's mkstemp's
    WriteText(tmp / TempName(tmp / "room.map", dead, suffix), "partial");
  }
  WriteFileAtomically(tmp / "room.map", "new\n");
  EXPECT_EQ(Names(tmp.path()), std::vector<std::string>{"room.map"});
}

TEST(WriteFileAtomically, KeepsLiveWritersFilesAndEveryOtherName) {
  const TempDir tmp;
  const pid_t dead = DeadPid();
  std::string other_owner = TempName(tmp / "room.map", dead, "0");
  other_owner.replace(other_owner.find("tmp-sgslam.") + 11, 4, "zzzz");  // another boot, host or container
  const std::vector<std::string> kept = {
      TempName(tmp / "room.map", getppid(), "3"),          // its writer is alive
      TempName(tmp / "room.map", dead, "17-characters-x"),  // not a suffix a writer gives
      TempName(tmp / "room.map", dead, "seventeen_chars_x"),
      TempName(tmp / "other.map", dead, "0"),  // another output's
      other_owner,
      "room.map.tmp.12345.old",  // a user's own names
      "room.map.tmp-sgslam.backup"};
  for (const std::string& name : kept) WriteText(tmp / name, "keep");
  WriteFileAtomically(tmp / "room.map", "new\n");
  std::vector<std::string> expected = kept;
  expected.push_back("room.map");
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(Names(tmp.path()), expected);
}

}  // namespace
}  // namespace sgslam
