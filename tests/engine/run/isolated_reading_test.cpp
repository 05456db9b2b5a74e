#include "engine/run/isolated_reading.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <string>

#include "engine/job/job_error.hpp"
#include "engine/run/job_runner.hpp"

namespace ggk::engine {
namespace {

TEST(IsolatedReading, TheChildsExitStatusIsReturned) {
  EXPECT_EQ(read_isolated({"a.h5"}, [] { return 0; }), 0);
  EXPECT_EQ(read_isolated({"a.h5"}, [] { return 1; }), 1);
  // The work runs in another process: nothing it changes reaches this one.
  int touched = 0;
  EXPECT_EQ(read_isolated({"a.h5"},
                          [&] {
                            touched = 1;
                            return static_cast<int>(::getpid() != 0);
                          }),
            1);
  EXPECT_EQ(touched, 0);
}

TEST(IsolatedReading, WhatTheWorkThrowsIsThrownAgainAsTheSameKind) {
  try {
    read_isolated({"a.h5"}, []() -> int { throw UsageError("a.h5 is another job's"); });
    FAIL() << "no UsageError";
  } catch (const UsageError& e) {
    EXPECT_STREQ(e.what(), "a.h5 is another job's");
  }
  // A job file's error is a user error too (exit status 2).
  EXPECT_THROW(read_isolated({"a.h5"},
                             []() -> int {
                               throw JobError("job.toml", {3, 1}, "runs", "must be positive");
                             }),
               UsageError);
  try {
    read_isolated({"a.h5"}, []() -> int { throw RunFailure("run 3 failed"); });
    FAIL() << "no RunFailure";
  } catch (const RunFailure& e) {
    EXPECT_STREQ(e.what(), "run 3 failed");
  }
  try {
    read_isolated({"a.h5"}, []() -> int { throw std::logic_error("a bug"); });
    FAIL() << "no runtime_error";
  } catch (const UsageError&) {
    FAIL() << "an internal error became a user error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "a bug");
  }
}

// SIGABRT and SIGILL reach the child as signals under the sanitizers too
// (ASan handles SIGSEGV, SIGBUS and SIGFPE itself and exits with a report).
// A file whose size claims exhaust memory (ggk diff on a zip bomb said "internal
// error: std::bad_alloc"): a user error naming the files, not an internal one.
TEST(IsolatedReading, AnAllocationFailureIsNotEnoughMemoryNamingTheFiles) {
  try {
    read_isolated({"a.h5", "b.h5"}, []() -> int { throw std::bad_alloc(); });
    ADD_FAILURE() << "nothing thrown";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("not enough memory to read a.h5 or b.h5"),
              std::string::npos)
        << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a UsageError: " << e.what();
  }
}

TEST(IsolatedReading, ACrashIsAReadingCrashNamingTheFileAfterTheCleanUp) {
  for (const int signal : {SIGABRT, SIGILL}) {
    pid_t cleaned = 0;
    try {
      read_isolated(
          {"shard-2.h5"},
          [&]() -> int {
            std::signal(signal, SIG_DFL);
            std::raise(signal);
            return 0;
          },
          [&](pid_t child) { cleaned = child; });
      FAIL() << "no ReadingCrash";
    } catch (const ReadingCrash& e) {
      EXPECT_EQ(e.file(), "shard-2.h5");
      EXPECT_EQ(e.how().rfind(signal == SIGABRT ? "SIGABRT (" : "SIGILL (", 0), 0u) << e.how();
      EXPECT_NE(std::string(e.what()).find("reading shard-2.h5 crashed the HDF5 library"),
                std::string::npos)
          << e.what();
    }
    EXPECT_GT(cleaned, 0);
    EXPECT_NE(cleaned, ::getpid());
  }
}

TEST(IsolatedReading, AnExitWithoutAReportIsACrash) {
  // What a sanitizer does with a SIGSEGV: print, then exit(1) unreported.
  const ChildEnd end = run_in_child([]() -> int { std::_Exit(1); });
  EXPECT_EQ(end.signal, 0);
  EXPECT_EQ(end.exit_status, 1);
  EXPECT_FALSE(end.reported);
  EXPECT_TRUE(crashed(end));
  EXPECT_EQ(ending_words(end), "an exit (status 1) without a report");
  const ChildEnd whole = run_in_child([] { return 1; });
  EXPECT_TRUE(whole.reported);
  EXPECT_FALSE(crashed(whole));
}

TEST(IsolatedReadingDeathTest, AnotherSignalEndsTheCallerBySameSignal) {
  // Ctrl-C or SIGPIPE is not a damaged file: ggk ends as the child did.
  EXPECT_EXIT(read_isolated({"a.h5"},
                            []() -> int {
                              std::raise(SIGTERM);
                              return 0;
                            }),
              testing::KilledBySignal(SIGTERM), "");
}

}  // namespace
}  // namespace ggk::engine
