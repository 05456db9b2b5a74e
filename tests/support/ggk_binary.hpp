#pragma once
// The `ggk` binary as a user runs it: a separate process whose exit status,
// stdout and stderr a test reads. ctest sets GGK_BINARY_DIR (tests/CMakeLists.txt).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/files.hpp"

namespace ggk::test_support {

// The exit status ggk gives for the user's mistakes.
constexpr int kUserError = 2;

struct Outcome {
  int status = -1;  // exit status, or -1 when the process did not exit normally
  std::string out;
  std::string err;
};

// Limits for a binary that a broken check could let run away.
struct ProcessLimits {
  std::int64_t address_space_kib = 0;  // `ulimit -v`; 0: none
  std::int32_t timeout_seconds = 0;    // `timeout`; 0: none
};

// "<GGK_BINARY_DIR>/ggk", or empty when the variable is not set (outside ctest).
std::filesystem::path ggk_binary();

// Runs `binary args...` with stdin from /dev/null and waits for it; stdout and
// stderr pass through files in `scratch` (removed afterwards).
Outcome run_binary(const std::filesystem::path& binary, const std::vector<std::string>& args,
                   const std::filesystem::path& scratch, const ProcessLimits& limits = {});

// Passes when `text` contains `part`, else says what it holds.
::testing::AssertionResult contains(const std::string& text, const std::string& part);

// A test of the binary: skipped outside ctest; a scratch folder `dir_` per test.
class GgkBinaryTest : public ::testing::Test {
 protected:
  void SetUp() override;

  // ggk with `args`, run in no particular folder.
  Outcome ggk(const std::vector<std::string>& args, const ProcessLimits& limits = {}) const {
    return run_binary(binary_, args, dir_, limits);
  }

  std::filesystem::path binary_;
  std::unique_ptr<ScratchDir> scratch_;
  std::filesystem::path dir_;
};

}  // namespace ggk::test_support
