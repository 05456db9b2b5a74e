#include "support/ggk_binary.hpp"

#include <sys/wait.h>

#include <cstdlib>

#include "engine/job/shell_words.hpp"

namespace ggk::test_support {

namespace fs = std::filesystem;
using engine::shell_quoted;

fs::path ggk_binary() {
  const char* binary_dir = std::getenv("GGK_BINARY_DIR");
  return binary_dir == nullptr ? fs::path() : fs::path(binary_dir) / "ggk";
}

Outcome run_binary(const fs::path& binary, const std::vector<std::string>& args,
                   const fs::path& scratch, const ProcessLimits& limits) {
  std::string command;
  if (limits.address_space_kib > 0) {
    command += "ulimit -v " + std::to_string(limits.address_space_kib) + "; ";
  }
  command += "exec ";
  if (limits.timeout_seconds > 0)
    command += "timeout " + std::to_string(limits.timeout_seconds) + " ";
  command += shell_quoted(binary.string());
  for (const std::string& arg : args) command += " " + shell_quoted(arg);
  const fs::path out = scratch / "ggk-stdout.txt", err = scratch / "ggk-stderr.txt";
  command += " </dev/null >" + shell_quoted(out.string()) + " 2>" + shell_quoted(err.string());
  const int raw = std::system(("bash -c " + shell_quoted(command)).c_str());
  Outcome outcome;
  if (raw != -1 && WIFEXITED(raw)) outcome.status = WEXITSTATUS(raw);
  outcome.out = file_bytes(out);
  outcome.err = file_bytes(err);
  std::error_code ignored;
  fs::remove(out, ignored);
  fs::remove(err, ignored);
  return outcome;
}

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

void GgkBinaryTest::SetUp() {
  binary_ = ggk_binary();
  if (binary_.empty()) GTEST_SKIP() << "GGK_BINARY_DIR is not set (run through ctest)";
  ASSERT_TRUE(fs::exists(binary_)) << binary_ << " is missing: build the ggk target";
  scratch_ = std::make_unique<ScratchDir>("ggk-binary");
  dir_ = scratch_->path();
}

}  // namespace ggk::test_support
