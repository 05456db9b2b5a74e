// process_state: this process runs; a child that exited is dead before it is
// reaped (a zombie) and after; a pid that names nothing is dead; a process's start
// time is its own.
#include "engine/store/process_state.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

namespace ggk::engine {
namespace {

TEST(ProcessState, ThisProcessRunsAndAnExitedChildDoesNot) {
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

TEST(ProcessState, AStartTimeIsKnownForThisProcessOnly) {
  EXPECT_FALSE(process_start(getpid()).empty());
  EXPECT_EQ(process_start(getpid()), process_start(getpid()));
  EXPECT_TRUE(process_start(0).empty());
}

TEST(ProcessState, ASleepingChildIsAlive) {
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
