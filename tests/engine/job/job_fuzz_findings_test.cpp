// Inputs the job-file fuzzer (fuzz/job_file_fuzzer.cpp) found, or that were
// written while fuzzing, each of which once did something other than parse or
// throw JobError. Each is read as the fuzzer reads it: parse_job() without output
// checks, in a folder with no input files.

#include <string>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

// What the fuzzer accepts: "ok" or the JobError's message. Any other exception
// fails the test by escaping it.
std::string fuzzer_outcome(const std::string& text) {
  JobLoadOptions options;
  options.check_output = false;
  try {
    parse_job(text, "fuzz/finding.toml", task_tables(), options);
  } catch (const JobError& error) {
    return error.what();
  }
  return "ok";
}

// A Khepera job with an inline arena; %STEPS% is steps_per_series.
std::string khepera_job(const std::string& steps_per_series) {
  return "name = \"k\"\ntask = \"khepera\"\nruns = 1\nseed = 2\n"
         "[sweep]\nkernels = [4]\nsigma = [1000.0]\n"
         "[khepera]\nseries = 4\nsteps_per_series = " +
         steps_per_series +
         "\n"
         "[khepera.arena]\nmin = [0.0, 0.0]\nmax = [40.0, 40.0]\nwalled = true\n"
         "start = { x = 10.0, y = 10.0, heading_deg = 45.0 }\n"
         "[khepera.som]\ngrid_from_samples = true\n";
}

TEST(JobFuzzFindings, KheperaStepsPerSeriesAtTheInt32MaximumIsRefusedWithoutOverflow) {
  // steps_per_series + 1 overflowed int (UBSan: signed integer overflow) and the
  // readings per run came out negative.
  EXPECT_EQ(fuzzer_outcome(khepera_job("2147483647")),
            "fuzz/finding.toml:10:1: [khepera] steps_per_series: series x (steps_per_series + 1) "
            "= 8589934592 readings per run, more than 2147483647");
  EXPECT_EQ(fuzzer_outcome(khepera_job("20")), "ok");
}

}  // namespace
}  // namespace ggk::engine
