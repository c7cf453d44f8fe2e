// Writing an output so that a crash, a kill or a full disk never leaves a torn file:
// a fresh temporary file beside it, flushed, then renamed over it. Temporary files
// are unnamed where the file system allows (O_TMPFILE); otherwise, and between
// naming and renaming, they are called "<path>.tmp-sgslam.<owner>.<pid>.<suffix>",
// where <owner> tells this boot of this machine and its PID namespace. Such a file
// whose writer is gone (SIGKILL, a power cut) is removed by the next writer of path.
#pragma once

#include <filesystem>
#include <string>

namespace sgslam {

// Writes content to path atomically (created exclusively, so a planted link is
// never followed; readers see the old or the new file). Throws InputError naming
// the path on failure, leaving no temporary file.
void WriteFileAtomically(const std::filesystem::path& path, const std::string& content);

// The start of the temporary names of path's writers in this process:
// "<path>.tmp-sgslam.<owner>.<pid>."; a writer in another program (bag_writer.py)
// adds a suffix of letters, digits or '_' (at most 16).
std::string TempFilePrefix(const std::filesystem::path& path);

// Removes path's temporary files whose writer is gone: their <owner> is this one's
// and no process has their <pid>. A reused id keeps its file until that process
// ends; a file of another boot, host or container is left alone.
void RemoveStaleTempFiles(const std::filesystem::path& path);

}  // namespace sgslam
