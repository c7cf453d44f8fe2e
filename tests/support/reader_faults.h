// Helpers for the readers' tests (issue #47): files that are not regular files,
// sparse files that claim much, and the message a reader's refusal gives.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <future>
#include <initializer_list>
#include <optional>
#include <string>

#include <gtest/gtest.h>

namespace sgslam::test {

// A FIFO at path; the test fails when it cannot be made.
inline void MakeFifo(const std::filesystem::path& path) {
  ASSERT_EQ(mkfifo(path.c_str(), 0644), 0) << path;
}

// A file of `bytes` zeros that takes no disk space (a hole).
inline void MakeSparse(const std::filesystem::path& path, std::uint64_t bytes) {
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0) << path;
  ASSERT_EQ(ftruncate(fd, static_cast<off_t>(bytes)), 0) << path;
  close(fd);
}

// The message of the exception E that fn throws within `seconds`; a failure, and
// nullopt, when it throws nothing or something else, or takes longer. A reader
// blocked on a FIFO is released (a writer opens it) so that the test ends.
template <class E>
std::optional<std::string> RefusalOf(const std::function<void()>& fn, double seconds = 10,
                                     const std::filesystem::path& fifo = {}) {
  auto done = std::async(std::launch::async, [&]() -> std::optional<std::string> {
    try {
      fn();
    } catch (const E& e) {
      return std::string(e.what());
    } catch (const std::exception& e) {
      ADD_FAILURE() << "another exception: " << e.what();
      return std::nullopt;
    }
    ADD_FAILURE() << "nothing thrown";
    return std::nullopt;
  });
  if (done.wait_for(std::chrono::duration<double>(seconds)) != std::future_status::ready) {
    ADD_FAILURE() << "still reading after " << seconds << " s (blocked?)";
    if (!fifo.empty()) {
      const int fd = open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
      if (fd >= 0) close(fd);
    }
  }
  return done.get();
}

// Every part appears in text.
inline void ExpectAll(const std::optional<std::string>& text, std::initializer_list<std::string> parts) {
  ASSERT_TRUE(text.has_value());
  for (const std::string& p : parts) EXPECT_NE(text->find(p), std::string::npos) << "'" << p << "' not in: " << *text;
}

}  // namespace sgslam::test
