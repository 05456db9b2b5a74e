// Messages stay short whatever the job file holds, and a job name that would
// make a file name too long is refused when the job is read, not when it runs.

#include "engine/job/job_error.hpp"

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

constexpr std::size_t kMaxMessageBytes = 600;

// The JobError message of `text`, read as jobs/hostile.toml without output checks.
std::string hostile_job_error(const std::string& text) {
  JobLoadOptions options;
  options.check_output = false;
  try {
    parse_job(text, "jobs/hostile.toml", task_tables(), options);
  } catch (const JobError& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected a JobError";
  return {};
}

constexpr const char* kMazeTables =
    "[sweep]\nkernels = [4]\nsigma = [2.0]\n"
    "[maze]\nmap = \"\"\"\n#####\n#..G#\n#####\n\"\"\"\n";

std::string job_named(const std::string& name) {
  return "name = \"" + name + "\"\ntask = \"maze\"\nruns = 1\nseed = 0\n" + kMazeTables;
}

// A dotted key in quotes (a study axis, `--sweep arm.links=...`) is one key:
// issue 36 found it printed as [sweep."arm] links".
TEST(DisplayKey, SplitsAtTheLastDotOutsideQuotes) {
  EXPECT_EQ(display_key("runs"), "runs");
  EXPECT_EQ(display_key("lspi.max_iterations"), "[lspi] max_iterations");
  EXPECT_EQ(display_key("khepera.motion.turn_deg"), "[khepera.motion] turn_deg");
  EXPECT_EQ(display_key("sweep.\"arm.links\""), "[sweep] \"arm.links\"");
  EXPECT_EQ(display_key("\"a.b\""), "\"a.b\"");
}

TEST(Shortened, KeepsShortTextAndCutsLongText) {
  EXPECT_EQ(shortened("abc", 3), "abc");
  EXPECT_EQ(shortened("abcd", 3), "abc\u2026(4 characters)");
  EXPECT_EQ(shortened(std::string(1000000, 'x')),
            std::string(80, 'x') + "\u2026(1000000 characters)");
}

TEST(Shortened, CountsCharactersAndNeverSplitsOne) {
  const std::string e_acute = "\u00e9";  // two bytes in UTF-8
  EXPECT_EQ(shortened(e_acute + e_acute + e_acute, 3), e_acute + e_acute + e_acute);
  EXPECT_EQ(shortened(e_acute + e_acute + e_acute, 2), e_acute + e_acute + "\u2026(3 characters)");
}

TEST(JobName, ANameOfAHundredCharactersIsAccepted) {
  JobLoadOptions options;
  options.check_output = false;
  const std::string name(100, 'n');
  EXPECT_EQ(parse_job(job_named(name), "jobs/long.toml", task_tables(), options).name, name);
}

TEST(JobName, ANameTooLongForAFileNameIsRefused) {
  const std::string message = hostile_job_error(job_named(std::string(300, 'n')));
  EXPECT_NE(message.find("jobs/hostile.toml:1:1: name: expected at most 100 characters"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("got 300"), std::string::npos) << message;
  EXPECT_LT(message.size(), kMaxMessageBytes) << message;
}

TEST(JobName, AnInvalidNameIsEchoedShortened) {
  const std::string message = hostile_job_error(job_named(std::string(99, 'n') + "/"));
  EXPECT_NE(message.find("expected letters, digits"), std::string::npos) << message;
  EXPECT_NE(message.find("\u2026(100 characters)"), std::string::npos) << message;
}

TEST(JobMessages, AMegabyteValueGivesAShortMessage) {
  const std::string huge(1 << 20, 'x');
  const std::string head = "name = \"a\"\ntask = \"maze\"\nruns = 1\nseed = 0\n";
  const std::string cases[] = {
      job_named(huge),                            // the name
      "name = \"a\"\ntask = \"" + huge + "\"\n",  // a choice
      "name = \"a\"\n" + huge + " = 1\n",         // an unknown key
      "name = \"a\"\n[" + huge + "]\nx = 1\n",    // an unknown table
      head + "[sweep]\nkernels = [4]\nsigma = [2.0]\n[maze]\nmap_file = \"" + huge +
          "\"\n",                                                  // a file name
      head + kMazeTables + "[output]\nfile = \"" + huge + "\"\n",  // the output file
      head + kMazeTables + "[output]\nfile = \"" + huge + "/x.h5\"\n",
  };
  for (const std::string& text : cases) {
    JobLoadOptions options;  // output checks on: the output file case needs them
    try {
      parse_job(text, "jobs/hostile.toml", task_tables(), options);
      ADD_FAILURE() << "expected a JobError for " << text.substr(0, 80);
    } catch (const JobError& error) {
      const std::string message = error.what();
      EXPECT_LT(message.size(), kMaxMessageBytes) << message.substr(0, 400);
    }
  }
}

}  // namespace
}  // namespace ggk::engine
