#pragma once
// The maze job the runner's and the results file's tests run: 3 runs x (2 bases
// x 2 kernel counts x 2 solvers) on a 27-state map, a fraction of a second, with
// slip so that sampling and the policy tests draw random numbers. Its fixture
// `JobRunnerTest` (a scratch folder, jobs loaded from it) is shared by
// tests/engine/run/job_runner_test.cpp and open_results_test.cpp.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "engine/job/job_spec.hpp"
#include "engine/run/job_runner.hpp"
#include "support/files.hpp"

namespace ggk::test_support {

// Two small rooms and a corridor: 27 states, one of them the goal.
extern const char* const kSmallMap;

// The determinism job writing to `output` (its [output] file).
std::string determinism_job(const std::filesystem::path& output);

// Options of a quiet run writing `output` with `threads` threads.
engine::RunOptions options_for(const std::filesystem::path& output, std::int32_t threads = 2);

// A scratch folder per test, removed afterwards.
class JobRunnerTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override { scratch_.reset(); }

  // Writes `text` to <dir>/<name> and loads it as a job.
  engine::JobSpec load_job(const std::string& name, const std::string& text) const;

  std::unique_ptr<ScratchDir> scratch_;
  std::filesystem::path dir_;
};

}  // namespace ggk::test_support
