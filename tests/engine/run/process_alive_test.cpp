// process_alive: this process runs; a child that exited is dead before it is
// reaped (a zombie) and after; a pid that names nothing is dead.
#include "engine/run/process_alive.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

namespace ggk::engine {
namespace {

TEST(ProcessAlive, ThisProcessRunsAndAnExitedChildDoesNot) {
  EXPECT_TRUE(process_alive(getpid()));
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) _exit(0);
  // Once it has exited, before it is reaped: a zombie (WNOWAIT leaves it one).
  siginfo_t info{};
  ASSERT_EQ(waitid(P_PID, static_cast<id_t>(child), &info, WEXITED | WNOWAIT), 0);
  EXPECT_FALSE(process_alive(child));
  ASSERT_EQ(waitpid(child, nullptr, 0), child);
  EXPECT_FALSE(process_alive(child));
  EXPECT_FALSE(process_alive(0));
  EXPECT_FALSE(process_alive(-5));
}

TEST(ProcessAlive, ASleepingChildIsAlive) {
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    pause();
    _exit(0);
  }
  EXPECT_TRUE(process_alive(child));
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
}

}  // namespace
}  // namespace ggk::engine
