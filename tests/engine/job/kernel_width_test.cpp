// Kernel widths at which every kernel value underflows to 0 or rounds to 1 are
// refused when the job is read, for every task, with a message that says why;
// widths around the tasks' calibrated ones are accepted.

#include "engine/job/kernel_width.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/tasks/task_list.hpp"
#include "support/shipped_jobs.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

// The CI job of `task` (support/shipped_jobs.hpp), its text with its [sweep]
// sigma line replaced by `sigma`.
std::string shipped_job_with_sigma(const fs::path& path, const std::string& sigma) {
  std::ifstream file(path);
  std::ostringstream text;
  text << file.rdbuf();
  std::string job = text.str();
  const std::size_t at = job.find("\nsigma = ");
  if (at == std::string::npos) return {};
  const std::size_t end = job.find('\n', at + 1);
  return job.replace(at + 1, end - at - 1, "sigma = " + sigma);
}

// "ok" or the JobError message of the shipped CI job of `task` with `sigma`.
std::string outcome(const std::string& task, const std::string& sigma) {
  const std::optional<fs::path> path = test_support::ci_job_for(task);
  if (!path) return "no CI job (jobs/ci*.toml) runs task " + task;
  const std::string text = shipped_job_with_sigma(*path, sigma);
  if (text.empty()) return "no job text";
  JobLoadOptions options;
  options.check_output = false;
  try {
    parse_job(text, *path, task_tables(), options);
  } catch (const JobError& error) {
    return error.what();
  }
  return "ok";
}

class KernelWidths : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    if (std::getenv("GGK_SOURCE_DIR") == nullptr) GTEST_SKIP() << "run through ctest";
  }
};

TEST_P(KernelWidths, TheSmallestPositiveDoubleIsRefusedAsAllZero) {
  const std::string message = outcome(GetParam(), "[5e-324]");
  EXPECT_NE(message.find("[sweep] sigma: sigma = 5e-324 is too small"), std::string::npos)
      << message;
  EXPECT_NE(message.find("underflows to 0"), std::string::npos) << message;
}

TEST_P(KernelWidths, TheLargestDoublesAreRefusedAsAllOne) {
  for (const char* sigma : {"[1.7e308]", "[1e200]"}) {
    const std::string message = outcome(GetParam(), sigma);
    EXPECT_NE(message.find("is too large"), std::string::npos) << message;
    EXPECT_NE(message.find("rounds to 1"), std::string::npos) << message;
  }
}

TEST_P(KernelWidths, TheBadWidthAmongGoodOnesIsNamed) {
  const std::string message = outcome(GetParam(), "[5.0, 1e300]");
  EXPECT_NE(message.find("sigma = 1e+300 is too large"), std::string::npos) << message;
}

TEST_P(KernelWidths, WidthsAroundTheCalibratedOnesAreAccepted) {
  EXPECT_EQ(outcome(GetParam(), "[0.5, 1, 2.5, 5.0, 10.0, 20.0, 250.0, 1000.0, 2000.0, 1e5]"),
            "ok");
}

// Every registered task, through its CI job: a new task is covered at once.
INSTANTIATE_TEST_SUITE_P(EveryTask, KernelWidths,
                         ::testing::ValuesIn(test_support::registered_task_names()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           return test_support::parameter_name(param.param);
                         });

}  // namespace
}  // namespace ggk::engine
