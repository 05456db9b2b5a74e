// Two job texts compared as parsed TOML.

#include "engine/job/job_compare.hpp"

#include <gtest/gtest.h>

namespace ggk::engine {
namespace {

constexpr const char* kJob = R"(name = "j"  # the name
runs = 3
[sweep]
kernels = [10, 20]
[maze]
series = 20
)";

TEST(JobDifference, CommentsLayoutAndKeyOrderDoNotCount) {
  const char* same = R"(# a comment added later
runs   =   3
name = 'j'

[maze]
series = 20   # unchanged
[sweep]
kernels = [ 10,
            20 ]
)";
  EXPECT_EQ(job_difference(kJob, same), std::nullopt);
}

TEST(JobDifference, NamesTheFirstChangedKey) {
  const std::string changed = R"(name = "j"
runs = 3
[sweep]
kernels = [10, 30]
[maze]
series = 20
)";
  const auto difference = job_difference(kJob, changed);
  ASSERT_TRUE(difference);
  EXPECT_EQ(*difference, "[sweep] kernels: [10, 20] in the results file, [10, 30] in the job file");
}

TEST(JobDifference, NamesKeysOnOneSideOnlyAndTypeChanges) {
  EXPECT_EQ(job_difference(kJob, "seed = 1\n" + std::string(kJob)),
            std::optional<std::string>("seed: only in the job file"));
  EXPECT_EQ(job_difference(std::string(kJob) + "[lspi]\ngamma = 0.9\n", kJob),
            std::optional<std::string>("lspi: only in the results file"));
  const auto type = job_difference("runs = 3\n", "runs = 3.0\n");
  ASSERT_TRUE(type);
  EXPECT_EQ(*type, "runs: 3 in the results file, 3.0 in the job file");
}

// Issue 37, cosmetics: a float is shown as written (0.2), not as toml++ prints it
// (0.20000000000000001), in arrays too.
TEST(JobDifference, NumbersAreShownInTheirShortestForm) {
  const auto difference = job_difference("[maze]\nslip = 0.2\n", "[maze]\nslip = 0.1\n");
  ASSERT_TRUE(difference);
  EXPECT_EQ(*difference, "[maze] slip: 0.2 in the results file, 0.1 in the job file");
  const auto array = job_difference("a = [0.2, 1e-06]\n", "a = [0.3]\n");
  ASSERT_TRUE(array);
  EXPECT_EQ(*array, "a: [0.2, 1e-06] in the results file, [0.3] in the job file");
}

TEST(JobDifference, TextsThatDoNotParseAreComparedAsText) {
  EXPECT_EQ(job_difference("x = [", "x = ["), std::nullopt);
  EXPECT_TRUE(job_difference("x = [", "x = 1"));
}

}  // namespace
}  // namespace ggk::engine
