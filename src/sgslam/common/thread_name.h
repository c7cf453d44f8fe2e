// Names the calling thread (as `top -H`, gdb and /proc/<pid>/task/*/comm show it).
// sgslam's threads are named "sg-<role>"; Linux keeps at most 15 characters.
#pragma once

#include <pthread.h>

namespace sgslam {

inline void NameThisThread(const char* name) { pthread_setname_np(pthread_self(), name); }

}  // namespace sgslam
