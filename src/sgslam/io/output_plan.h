// Where a command may write. Every file a command writes is listed here with the
// files and folders it reads, and checked before anything is written, so that a
// refused command changes nothing:
//   - never into a folder it reads files of by name (the dataset, its images, the
//     detector's model), nor over a file it reads (a configuration, a map, a
//     vocabulary, a trajectory);
//   - never two outputs under one name (the second would replace the first);
//   - never into a system folder (/, /etc, /usr, /dev, ...);
//   - an existing file is replaced only where the command's contract says so: in
//     its output folder, or where it holds an output of the same kind (a map over
//     a map, a PNG plot over a PNG); never a folder, FIFO or device.
// Paths are compared after resolving links and "..", so another spelling of the
// same file is caught; both the name given and the file it links to are a read
// file's (writing replaces the name, and the link would be lost).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace sgslam {

class OutputPlan {
 public:
  // `role` names the path in errors: "--config", "the dataset folder", ...
  void Reads(const std::filesystem::path& file, const std::string& role);
  void ReadsFolder(const std::filesystem::path& folder, const std::string& role);
  // A folder the command creates (when missing) and writes its outputs into, whose
  // files of those names it may replace.
  void WritesFolder(const std::filesystem::path& folder, const std::string& role);
  // A file the command writes. When `signature` is not empty (a file an option
  // names), an existing file is replaced only if it is a regular file that is empty
  // or begins with those bytes (an earlier output of the same kind). Without one (a
  // file of an output folder), what is there is the folder's, replaced by the
  // output (a folder in its place fails that output alone, when it is written).
  void Writes(const std::filesystem::path& file, const std::string& role, const std::string& signature = "");

  // Throws InputError naming both paths of the first rule broken.
  void Check() const;

 private:
  struct Entry {
    std::filesystem::path path;  // as given
    std::filesystem::path key;   // resolved: links, "." and ".." out
    std::string role, signature;
  };
  void CheckFolder(const Entry& folder) const;
  void CheckFile(const Entry& file, std::size_t index) const;
  void CheckAgainstOtherOutputs(const Entry& file, std::size_t index) const;

  std::vector<Entry> reads_, read_folders_, write_folders_, writes_;
};

// True for the root folder, the top-level folders of the system, and the folders
// of the system's own files below them (/etc, /usr, /boot, /dev but /dev/shm, ...).
// `folder` is resolved first.
bool IsSystemFolder(const std::filesystem::path& folder);

}  // namespace sgslam
