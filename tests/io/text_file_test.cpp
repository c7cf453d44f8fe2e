#include "sgslam/io/text_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <sstream>

#include "sgslam/common/error.h"
#include "sgslam/io/atomic_write.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

std::string Read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> Names(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(WriteFileAtomically, ReplacesTheFileAndLeavesNothingElse) {
  const TempDir tmp;
  WriteFileAtomically(tmp / "a.txt", "first\n");
  WriteFileAtomically(tmp / "a.txt", "second\n");
  EXPECT_EQ(Read(tmp / "a.txt"), "second\n");
  EXPECT_EQ(Names(tmp.path()), std::vector<std::string>{"a.txt"});
}

TEST(WriteFileAtomically, GivesAnOrdinaryNewFilesPermissions) {
  const TempDir tmp;
  const mode_t old = umask(027);
  WriteFileAtomically(tmp / "a.txt", "x");
  umask(old);
  struct stat st {};
  ASSERT_EQ(stat((tmp / "a.txt").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u);
}

TEST(WriteFileAtomically, ReplacesALinkNotItsTarget) {
  const TempDir tmp;
  WriteFileAtomically(tmp / "target.txt", "keep\n");
  fs::create_symlink(tmp / "target.txt", tmp / "out.txt");
  fs::create_symlink(tmp / "target.txt", tmp / "out.txt.tmp");  // a planted fixed temporary name
  WriteFileAtomically(tmp / "out.txt", "new\n");
  EXPECT_EQ(Read(tmp / "target.txt"), "keep\n");
  EXPECT_FALSE(fs::is_symlink(tmp / "out.txt"));
  EXPECT_EQ(Read(tmp / "out.txt"), "new\n");
}

TEST(WriteFileAtomically, AFailedWriteLeavesNoTemporaryFile) {
  const TempDir tmp;
  fs::create_directories(tmp / "out.txt");  // a folder where the file should go: the rename fails
  EXPECT_THROW(WriteFileAtomically(tmp / "out.txt", "x"), InputError);
  EXPECT_EQ(Names(tmp.path()), std::vector<std::string>{"out.txt"});
}

TEST(ForEachDataLine, RefusesALineWithANulByte) {
  const TempDir tmp;
  {
    std::ofstream f(tmp / "rgb.txt", std::ios::binary);
    f << "# list\n1.0 rgb/1.png\n2.0 rgb/2.png" << '\0' << "../../etc/passwd\n";
  }
  int lines = 0;
  try {
    ForEachDataLine(tmp / "rgb.txt", [&](int, const std::vector<std::string_view>&) { ++lines; });
    FAIL() << "a NUL byte was accepted";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("NUL byte"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(":3"), std::string::npos) << e.what();
  }
  EXPECT_EQ(lines, 1);
}

}  // namespace
}  // namespace sgslam
