#include "engine/run/resume_command.hpp"

#include <gtest/gtest.h>

#include <string>

#include "engine/run/job_runner.hpp"

namespace ggk::engine {
namespace {

JobSpec job_with_overrides() {
  JobSpec job;
  job.source_file = "jobs/ci.toml";
  job.overrides = {"runs=5", "maze.slip=0.1"};
  job.sweeps = {"kernels=10,20"};
  return job;
}

TEST(ResumeCommand, RepeatsTheInvocationWithResume) {
  RunOptions options;
  options.invocation = {"build/ggk", "run",     "jobs/ci.toml",  "--set", "runs=5",          "-j",
                        "2",         "--sweep", "kernels=10,20", "-o",    "my results/ci.h5"};
  EXPECT_EQ(resume_command(JobSpec(), options, "my results/ci.h5"),
            "build/ggk run jobs/ci.toml --set runs=5 -j 2 --sweep kernels=10,20 -o "
            "'my results/ci.h5' --resume");
}

TEST(ResumeCommand, OverwriteBecomesResumeAndResumeIsNotRepeated) {
  RunOptions options;
  options.invocation = {"ggk", "run", "jobs/ci.toml", "--overwrite", "-o", "x.h5"};
  EXPECT_EQ(resume_command(JobSpec(), options, "x.h5"), "ggk run jobs/ci.toml --resume -o x.h5");
  options.invocation = {"ggk", "run", "jobs/ci.toml", "--resume", "--runs", "0:3", "-o", "x.h5"};
  EXPECT_EQ(resume_command(JobSpec(), options, "x.h5"),
            "ggk run jobs/ci.toml --resume --runs 0:3 -o x.h5");
  // Before a "--", after which the words are not options.
  options.invocation = {"ggk", "run", "-o", "x.h5", "--", "jobs/ci.toml"};
  EXPECT_EQ(resume_command(JobSpec(), options, "x.h5"), "ggk run -o x.h5 --resume -- jobs/ci.toml");
}

TEST(ResumeCommand, WithoutAnInvocationTheJobAndOptionsMakeIt) {
  RunOptions options;
  options.runs = RunRange{2, 4};
  options.overwrite = true;
  EXPECT_EQ(resume_command(job_with_overrides(), options, "out.h5"),
            "ggk run jobs/ci.toml --set runs=5 --set maze.slip=0.1 --sweep kernels=10,20 --runs "
            "2:4 -o out.h5 --resume");
}

TEST(ResumeCommand, TheUnpublishedTextSaysWhatOverwriteDeletes) {
  RunOptions options;
  options.invocation = {"ggk", "run", "jobs/ci.toml", "--overwrite", "-o", "x.h5"};
  const GoOnText text = go_on_text(JobSpec(), options, "x.h5", false);
  EXPECT_EQ(text.published,
            "every run written to x.h5 is complete; finish the job with `ggk run jobs/ci.toml "
            "--resume -o x.h5`");
  EXPECT_EQ(text.unpublished,
            "x.h5 is as it was (no run of this job was written); start the job again with `ggk "
            "run jobs/ci.toml --overwrite -o x.h5`, whose --overwrite deletes the runs x.h5 holds");
  const GoOnText mpi = go_on_text(JobSpec(), options, "x.h5", true);
  EXPECT_NE(mpi.published.find("` (under mpirun as before, with any number of ranks, or alone)"),
            std::string::npos);
}

}  // namespace
}  // namespace ggk::engine
