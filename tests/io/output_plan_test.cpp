#include "sgslam/io/output_plan.h"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <string>

#include "sgslam/common/error.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::TempDir;
using test::WriteText;

// The error Check() throws; a failure when it throws none.
std::string Refusal(const OutputPlan& plan) {
  try {
    plan.Check();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "the plan was accepted";
  return "";
}

TEST(OutputPlan, AcceptsNewFilesInAFolderOfTheirOwn) {
  const TempDir tmp;
  WriteText(tmp / "data" / "rgb.txt", "x\n");
  OutputPlan plan;
  plan.ReadsFolder(tmp / "data", "the dataset folder");
  plan.Reads(tmp / "c.yaml", "--config");
  plan.WritesFolder(tmp / "out", "--out");
  plan.Writes(tmp / "out" / "trajectory.txt", "the run's trajectory.txt");
  plan.Writes(tmp / "maps" / "room.map", "--save-map", "SGMAP");
  plan.Writes(tmp / "data" / "results" / "a.txt", "--x");  // a new folder inside the dataset's reads nothing
  EXPECT_NO_THROW(plan.Check());
}

TEST(OutputPlan, RefusesTheDatasetFolderAndFilesInIt) {
  const TempDir tmp;
  WriteText(tmp / "data" / "associations.txt", "x\n");
  OutputPlan folder;
  folder.ReadsFolder(tmp / "data", "the dataset folder");
  folder.WritesFolder(tmp / "data" / "." / "sub" / "..", "--out");  // another spelling of the same folder
  const std::string why = Refusal(folder);
  EXPECT_NE(why.find("the dataset folder"), std::string::npos) << why;

  OutputPlan file;
  file.ReadsFolder(tmp / "data", "the dataset folder");
  file.Writes(tmp / "data" / "associations.txt", "--save-map", "SGMAP");
  const std::string file_why = Refusal(file);
  EXPECT_NE(file_why.find("--save-map"), std::string::npos) << file_why;
  EXPECT_NE(file_why.find((tmp / "data").string()), std::string::npos) << file_why;
}

TEST(OutputPlan, RefusesAFileReadUnderAnyNameOrLink) {
  const TempDir tmp;
  WriteText(tmp / "c.yaml", "orb: {features: 900}\n");
  fs::create_symlink(tmp / "c.yaml", tmp / "link.yaml");
  for (const fs::path& written : {tmp / "c.yaml", tmp / "sub" / ".." / "c.yaml", tmp / "link.yaml"}) {
    fs::create_directories(tmp / "sub");
    OutputPlan plan;
    plan.Reads(tmp / "link.yaml", "the configuration file (--config)");
    plan.Writes(written, "--save-map", "SGMAP");
    const std::string why = Refusal(plan);
    EXPECT_NE(why.find("the configuration file (--config)"), std::string::npos) << written << ": " << why;
  }
}

TEST(OutputPlan, RefusesTwoOutputsUnderOneName) {
  const TempDir tmp;
  OutputPlan plan;
  plan.WritesFolder(tmp / "out", "--out");
  plan.Writes(tmp / "out" / "trajectory.txt", "the run's trajectory.txt");
  plan.Writes(tmp / "out" / "trajectory.txt", "--save-map", "SGMAP");
  const std::string why = Refusal(plan);
  EXPECT_NE(why.find("--save-map"), std::string::npos) << why;
  EXPECT_NE(why.find("is also the run's trajectory.txt"), std::string::npos) << why;
}

TEST(OutputPlan, ReplacesAnExistingFileOnlyOfItsOwnKind) {
  const TempDir tmp;
  WriteText(tmp / "notes.txt", "my notes\n");
  WriteText(tmp / "old.map", std::string("SGMAP\0\0\0 and the rest", 20));
  WriteText(tmp / "empty.map", "");
  OutputPlan notes;
  notes.Writes(tmp / "notes.txt", "--save-map", std::string("SGMAP\0\0\0", 8));
  EXPECT_NE(Refusal(notes).find("exists and is not a file this command writes"), std::string::npos);
  for (const char* name : {"old.map", "empty.map"}) {
    OutputPlan plan;
    plan.Writes(tmp / name, "--save-map", std::string("SGMAP\0\0\0", 8));
    EXPECT_NO_THROW(plan.Check()) << name;
  }
  OutputPlan any;  // an output folder's file: its contract is to be replaced
  any.Writes(tmp / "notes.txt", "the run's trajectory.txt");
  EXPECT_NO_THROW(any.Check());
}

// A socket, as a file a device or another program's endpoint would be.
void MakeSocket(const fs::path& path) {
  const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  ASSERT_LT(path.string().size(), sizeof address.sun_path);
  std::strcpy(address.sun_path, path.c_str());
  ASSERT_EQ(bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
  close(fd);
}

TEST(OutputPlan, NeverReplacesAFolderFifoOrSocket) {
  const TempDir tmp;
  fs::create_directories(tmp / "folder.map");
  ASSERT_EQ(mkfifo((tmp / "fifo.map").c_str(), 0644), 0);
  MakeSocket(tmp / "socket.map");
  for (const fs::path& p : {tmp / "folder.map", tmp / "fifo.map", tmp / "socket.map"}) {
    OutputPlan plan;
    plan.Writes(p, "--save-map", "SGMAP");
    const std::string why = Refusal(plan);
    EXPECT_NE(why.find("only a regular file is ever replaced"), std::string::npos) << why;
  }
  OutputPlan device;
  device.Writes("/dev/null", "--save-map", "SGMAP");
  EXPECT_NE(Refusal(device).find("system folder"), std::string::npos);
}

TEST(OutputPlan, RefusesEmptyPaths) {
  OutputPlan folder;
  folder.WritesFolder("", "--out");
  EXPECT_EQ(Refusal(folder), "--out: an empty path");
  OutputPlan file;
  file.Writes("", "--save-map", "SGMAP");
  EXPECT_EQ(Refusal(file), "--save-map: an empty path");
}

TEST(OutputPlan, RefusesAFileWhereAnOutputNeedsAFolder) {
  const TempDir tmp;
  const auto refused = [&](const fs::path& out, const fs::path& map) {
    OutputPlan plan;
    plan.WritesFolder(out, "--out");
    plan.Writes(out / "stats.json", "the run's stats.json");
    plan.Writes(map, "--save-map", "SGMAP");
    return Refusal(plan);
  };
  EXPECT_NE(refused(tmp / "mm.map", tmp / "mm.map").find("--out"), std::string::npos);  // the same new name
  EXPECT_NE(refused(tmp / "maps" / "run1", tmp / "maps").find("is a folder there"), std::string::npos);
  EXPECT_NE(refused(tmp / "o3", tmp / "o3" / "stats.json" / "m.map").find("would be inside the run's stats.json"),
            std::string::npos);
}

TEST(OutputPlan, RefusesSystemFolders) {
  for (const char* folder : {"/", "/etc", "/usr/share", "/usr/local/lib", "/proc/self", "/dev", "/boot", "/var", "/home",
                             "/mnt", "/etc/../usr"}) {
    EXPECT_TRUE(IsSystemFolder(folder)) << folder;
    OutputPlan plan;
    plan.WritesFolder(folder, "--out");
    EXPECT_NE(Refusal(plan).find("is a system folder"), std::string::npos) << folder;
  }
  for (const char* folder :
       {"/tmp", "/tmp/x", "/var/tmp/run", "/home/someone/out", "/dev/shm", "/dev/shm/sgslam", "/opt/robot/maps", "/mnt/data"}) {
    EXPECT_FALSE(IsSystemFolder(folder)) << folder;
  }
}

}  // namespace
}  // namespace sgslam
