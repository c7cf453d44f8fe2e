#include "sgslam/common/data_dir.h"

namespace sgslam {

namespace fs = std::filesystem;

std::optional<fs::path> ExecutableDir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec || exe.empty()) return std::nullopt;
  return exe.parent_path();
}

std::optional<fs::path> DataDir() {
  const auto exe_dir = ExecutableDir();
  if (!exe_dir) return std::nullopt;
  for (const fs::path& candidate : {*exe_dir / "share" / "sgslam", *exe_dir / ".." / "share" / "sgslam"}) {
    std::error_code ec;
    if (fs::is_directory(candidate, ec)) return candidate.lexically_normal();
  }
  return std::nullopt;
}

}  // namespace sgslam
