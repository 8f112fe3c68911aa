// Tests of the progress bar: it draws on a terminal and stays silent on a pipe or file.
#include "cli/progress.h"

#include <fcntl.h>
#include <pty.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include <gtest/gtest.h>

namespace mocap {
namespace {

// Runs `work` with stderr redirected to `fd`, then restores it.
template <typename Work>
void WithStderr(int fd, Work work) {
  std::fflush(stderr);
  const int saved = dup(STDERR_FILENO);
  ASSERT_GE(saved, 0);
  dup2(fd, STDERR_FILENO);
  work();
  std::fflush(stderr);
  dup2(saved, STDERR_FILENO);
  close(saved);
}

std::string Drain(int fd) {
  std::string text;
  char buffer[4096];
  const int flags = fcntl(fd, F_GETFL);
  fcntl(fd, F_SETFL, flags | O_NONBLOCK);
  for (ssize_t n; (n = read(fd, buffer, sizeof(buffer))) > 0;) text.append(buffer, static_cast<size_t>(n));
  return text;
}

TEST(ProgressBarTest, SilentWhenStderrIsNotATerminal) {
  int pipe_fds[2];
  ASSERT_EQ(pipe(pipe_fds), 0);
  WithStderr(pipe_fds[1], [] {
    ProgressBar bar("work", 10);
    EXPECT_FALSE(bar.enabled());
    for (size_t i = 1; i <= 10; ++i) bar.Update(i);
  });
  close(pipe_fds[1]);
  EXPECT_EQ(Drain(pipe_fds[0]), "");
  close(pipe_fds[0]);
}

TEST(ProgressBarTest, DrawsOnATerminal) {
  int master = -1, slave = -1;
  if (openpty(&master, &slave, nullptr, nullptr, nullptr) != 0) GTEST_SKIP() << "no pseudo-terminal available";
  WithStderr(slave, [] {
    ProgressBar bar("frames", 4);
    EXPECT_TRUE(bar.enabled());
    for (size_t i = 1; i <= 4; ++i) bar.Update(i);
    bar.Finish();
  });
  const std::string text = Drain(master);
  EXPECT_NE(text.find("frames ["), std::string::npos) << text;
  EXPECT_NE(text.find("100%"), std::string::npos) << text;
  EXPECT_NE(text.find("4/4"), std::string::npos) << text;
  close(slave);
  close(master);
}

}  // namespace
}  // namespace mocap
