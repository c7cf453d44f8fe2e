// One read measured alone, in a forked child, for the readers' memory tests (issue
// #47). The test process's own peak resident memory (ru_maxrss) says nothing of
// one read once an earlier test in the process used more; a child's peak starts
// at its resident memory when forked, so its rise is what the read alone held.
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <functional>
#include <optional>
#include <string>

#include <gtest/gtest.h>

namespace sgslam::test {

struct ChildRefusal {
  std::optional<std::string> message;  // what the E thrown says; nullopt (and a failure) otherwise
  double peak_rise_mib = 0;            // the child's peak resident memory above its start
};

// Runs fn in a forked child and reports the message of the exception E it throws
// and the memory it held. gtest's failures in a child are lost, so the child only
// reports and the checks are the caller's; a child still reading after `seconds`
// is ended (SIGALRM) and that is a failure, as RefusalOf's watchdog.
template <class E>
ChildRefusal RefusalInChild(const std::function<void()>& fn, unsigned seconds = 60) {
  int fds[2];
  if (pipe(fds) != 0) {
    ADD_FAILURE() << "pipe() failed";
    return {};
  }
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    alarm(seconds);
    const auto peak_kib = [] {
      rusage usage{};
      getrusage(RUSAGE_SELF, &usage);
      return usage.ru_maxrss;
    };
    const long start = peak_kib();
    std::string outcome;  // "+message" for an E, "-why" for anything else
    try {
      fn();
      outcome = "-nothing thrown";
    } catch (const E& e) {
      outcome = std::string("+") + e.what();
    } catch (const std::exception& e) {
      outcome = std::string("-another exception: ") + e.what();
    }
    const std::string report = std::to_string(peak_kib() - start) + "\n" + outcome;
    for (std::size_t at = 0; at < report.size();) {
      const ssize_t n = write(fds[1], report.data() + at, report.size() - at);
      if (n <= 0) _exit(1);
      at += static_cast<std::size_t>(n);
    }
    _exit(0);  // not exit(): the parent's atexit handlers and gtest's are not the child's
  }
  close(fds[1]);
  std::string report;
  char buffer[4096];
  for (ssize_t n; pid > 0 && (n = read(fds[0], buffer, sizeof buffer)) > 0;) report.append(buffer, static_cast<std::size_t>(n));
  close(fds[0]);
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    ADD_FAILURE() << "the child did not report (fork failed, or it was ended: still reading after " << seconds
                  << " s?)";
    return {};
  }
  const std::size_t newline = report.find('\n');
  ChildRefusal result;
  result.peak_rise_mib = std::strtod(report.substr(0, newline).c_str(), nullptr) / 1024.0;
  const std::string outcome = newline == std::string::npos ? "-no report" : report.substr(newline + 1);
  if (!outcome.empty() && outcome[0] == '+') {
    result.message = outcome.substr(1);
  } else {
    ADD_FAILURE() << outcome.substr(outcome.empty() ? 0 : 1);
  }
  return result;
}

}  // namespace sgslam::test
