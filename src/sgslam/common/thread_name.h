// Names the calling thread (as `top -H`, gdb and /proc/<pid>/task/*/comm show it).
// sgslam's threads are named "sg-<role>"; Linux keeps at most 15 characters.
#pragma once

#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

namespace sgslam {

inline void NameThisThread(const char* name) { pthread_setname_np(pthread_self(), name); }

// The calling thread at the lowest CPU priority (Linux: per-thread nice 19): work for
// later or for a display (the semantic map, a recording) takes only the time that
// tracking and local mapping leave on two cores.
inline void LowerThisThreadsPriority() { setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 19); }

}  // namespace sgslam
