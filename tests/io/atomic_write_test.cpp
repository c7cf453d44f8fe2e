// WriteFileAtomically's clearing of the temporary files that killed writers left.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "sgslam/io/text_file.h"
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

TEST(WriteFileAtomically, RemovesTheTemporaryFilesOfDeadWriters) {
  const TempDir tmp;
  const std::string dead = std::to_string(DeadPid());
  WriteText(tmp / ("room.map.tmp." + dead + ".0"), "linked, not yet renamed");
  WriteText(tmp / ("room.map.tmp." + dead + ".aB3xY9"), "the fallback's name");
  WriteFileAtomically(tmp / "room.map", "new\n");
  EXPECT_EQ(Names(tmp.path()), std::vector<std::string>{"room.map"});
}

TEST(WriteFileAtomically, KeepsTheTemporaryFilesOfLiveWritersAndOtherNames) {
  const TempDir tmp;
  const std::string parent = std::to_string(getppid());  // alive, and started before the file was written
  const std::vector<std::string> kept = {"room.map.tmp." + parent + ".3", "room.map.tmp.1.7", "room.map.tmp.notes",
                                         "room.map.tmp.12345.old~", "other.map.tmp." + std::to_string(DeadPid()) + ".0"};
  for (const std::string& name : kept) WriteText(tmp / name, "keep");
  WriteFileAtomically(tmp / "room.map", "new\n");
  std::vector<std::string> expected = kept;
  expected.push_back("room.map");
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(Names(tmp.path()), expected);
}

TEST(WriteFileAtomically, RemovesAFileWhoseWritersIdWasReused) {
  const TempDir tmp;
  // The parent process is alive, but it started after this file was last written:
  // the writer that named it had the same id before.
  const fs::path stale = tmp / ("room.map.tmp." + std::to_string(getppid()) + ".2");
  WriteText(stale, "stale");
  fs::last_write_time(stale, fs::file_time_type::clock::now() - std::chrono::hours(24 * 365 * 20));
  WriteFileAtomically(tmp / "room.map", "new\n");
  EXPECT_EQ(Names(tmp.path()), std::vector<std::string>{"room.map"});
}

}  // namespace
}  // namespace sgslam
