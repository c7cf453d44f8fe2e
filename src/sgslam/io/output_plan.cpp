#include "sgslam/io/output_plan.h"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <string_view>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"

namespace sgslam {

namespace fs = std::filesystem;

namespace {

// The path with links, "." and ".." resolved as far as it exists.
fs::path Resolved(const fs::path& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) p = fs::absolute(path, ec).lexically_normal();
  if (p.has_filename() || p == p.root_path()) return p;
  return p.parent_path();  // "dir/" is dir
}

// A file's name as a rename sees it: its folder resolved, its own name kept (a
// link there is replaced, not followed).
fs::path NameKey(const fs::path& file) {
  std::error_code ec;
  return Resolved(fs::absolute(file, ec).parent_path()) / file.filename();
}

// One folder under two names: the same resolved path, or the same folder reached
// another way (a bind mount).
bool SameFolder(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  return a == b || fs::equivalent(a, b, ec);
}

bool Under(const fs::path& p, const fs::path& folder) {
  const auto [f, q] = std::mismatch(folder.begin(), folder.end(), p.begin(), p.end());
  return f == folder.end();
}

}  // namespace

bool IsSystemFolder(const fs::path& folder) {
  // The folders of the system itself: neither they nor anything below them.
  static const std::array<std::string_view, 12> kSystem = {"/bin", "/boot", "/dev",   "/etc", "/lib",  "/lib32",
                                                           "/lib64", "/libx32", "/proc", "/sbin", "/sys", "/usr"};
  // Folders that hold others' folders: not they, but a folder below them may be the user's.
  static const std::array<std::string_view, 7> kTop = {"/home", "/media", "/mnt", "/opt", "/run", "/srv", "/var"};
  const fs::path p = Resolved(folder);
  if (p == p.root_path()) return true;
  if (std::any_of(kTop.begin(), kTop.end(), [&](std::string_view t) { return p == fs::path(t); })) return true;
  if (Under(p, "/dev/shm")) return false;  // shared memory: scratch space, as /tmp
  return std::any_of(kSystem.begin(), kSystem.end(), [&](std::string_view s) { return Under(p, fs::path(s)); });
}

void OutputPlan::Reads(const fs::path& file, const std::string& role) {
  if (file.empty()) return;
  reads_.push_back({file, NameKey(file), role, ""});
  // The file a link names is read too.
  if (const fs::path target = Resolved(file); target != reads_.back().key) reads_.push_back({file, target, role, ""});
}

void OutputPlan::ReadsFolder(const fs::path& folder, const std::string& role) {
  if (!folder.empty()) read_folders_.push_back({folder, Resolved(folder), role, ""});
}

void OutputPlan::WritesFolder(const fs::path& folder, const std::string& role) {
  write_folders_.push_back({folder, folder.empty() ? fs::path() : Resolved(folder), role, ""});
}

void OutputPlan::Writes(const fs::path& file, const std::string& role, const std::string& signature) {
  writes_.push_back({file, file.empty() ? fs::path() : NameKey(file), role, signature});
}

void OutputPlan::CheckFolder(const Entry& w) const {
  const std::string what = w.role + " " + w.path.string();
  if (w.path.empty()) throw InputError(w.role + ": an empty path");
  if (IsSystemFolder(w.key)) {
    throw InputError(what + ": " + w.key.string() + " is a system folder; write into a folder of your own");
  }
  for (const Entry& r : read_folders_) {
    if (SameFolder(w.key, r.key)) {
      throw InputError(what + " is " + r.role + " (" + r.path.string() + "): the outputs would be written among the " +
                       "files it reads; choose another folder");
    }
  }
}

void OutputPlan::CheckFile(const Entry& w, std::size_t index) const {
  const std::string what = w.role + " " + w.path.string();
  if (w.path.empty()) throw InputError(w.role + ": an empty path");
  if (!w.path.has_filename()) throw InputError(what + ": names a folder, not a file");
  const fs::path folder = w.key.parent_path();
  if (IsSystemFolder(folder)) {
    throw InputError(what + ": " + folder.string() + " is a system folder; write into a folder of your own");
  }
  for (const Entry& r : read_folders_) {
    if (SameFolder(folder, r.key)) {
      throw InputError(what + ": would be written into " + r.role + " (" + r.path.string() +
                       "), among the files it reads; choose a file outside it");
    }
  }
  for (const Entry& r : reads_) {
    std::error_code ec;  // the same file under a name of another case (vfat), a bind mount, a hard link
    if (w.key == r.key || fs::equivalent(w.path, r.path, ec)) {
      throw InputError(what + " is " + r.role + " (" + r.path.string() + "): it is read, and writing would destroy " +
                       "it; choose another file");
    }
  }
  CheckAgainstOtherOutputs(w, index);
  // An output folder's file is the folder's: whatever is under its name is replaced
  // (a folder there fails that output alone when it is written, as its writer says).
  if (w.signature.empty()) return;
  struct stat st {};
  if (stat(w.path.c_str(), &st) != 0) return;  // a new file (or a dangling link, replaced)
  if (!S_ISREG(st.st_mode)) {
    throw InputError(what + ": " + WhyNotRegularFile(w.path) + "; only a regular file is ever replaced");
  }
  if (st.st_size == 0) return;
  const RegularFile existing(w.path, w.role);
  const std::size_t n = w.signature.size();
  if (existing.size() < n || existing.Read(0, n) != w.signature) {
    throw InputError(what + " exists and is not a file this command writes (it would be replaced and lost); remove " +
                     "it first, or choose another name");
  }
}

// Two outputs under one name, or one where another needs a folder.
void OutputPlan::CheckAgainstOtherOutputs(const Entry& w, std::size_t index) const {
  const std::string what = w.role + " " + w.path.string();
  for (const Entry& f : write_folders_) {
    if (SameFolder(w.key, f.key) || Under(f.key, w.key)) {
      throw InputError(what + ": " + f.role + " " + f.path.string() + " is a folder there; choose another name");
    }
  }
  for (std::size_t i = 0; i < index; ++i) {  // each pair once, blaming the later (an option's, added last)
    const Entry& o = writes_[i];
    if (w.key == o.key) {
      throw InputError(what + " is also " + o.role + " (" + o.path.string() + "): one would replace the other; " +
                       "choose another name");
    }
    if (Under(w.key, o.key) || Under(o.key, w.key)) {
      const bool inside = Under(w.key, o.key);
      throw InputError(what + (inside ? " would be inside " : " would hold ") + o.role + " (" + o.path.string() +
                       "), a file; choose another name");
    }
  }
}

void OutputPlan::Check() const {
  for (const Entry& w : write_folders_) CheckFolder(w);
  for (std::size_t i = 0; i < writes_.size(); ++i) CheckFile(writes_[i], i);
}

}  // namespace sgslam
