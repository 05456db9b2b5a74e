// ggk validate with an existing output (engine/run/resume_preview.hpp) says what
// `ggk run --resume` would compute before it runs, and refuses (with --resume)
// what run --resume would refuse; `ggk validate --print` prints the resolved job
// as a job file that reads back as the same job. Through the real binary.

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/determinism_job.hpp"
#include "support/files.hpp"
#include "support/ggk_binary.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

class ResumePreviewCli : public GgkBinaryTest {
 protected:
  void SetUp() override {
    GgkBinaryTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    output_ = dir_ / "out.h5";
    job_ = write_file(dir_ / "job.toml", determinism_job(output_));  // 3 runs x 8 fits
  }

  // ggk validate JOB with `extra` arguments.
  Outcome validate(std::vector<std::string> extra) const {
    std::vector<std::string> args = {"validate", job_.string(), "-o", output_.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return ggk(args);
  }

  fs::path job_, output_;
};

TEST_F(ResumePreviewCli, SaysWhatAResumeWouldComputeAndHowLongItsFitsTake) {
  const Outcome ran =
      ggk({"run", job_.string(), "-q", "--set", "runs=2", "-j", "2", "-o", output_.string()});
  ASSERT_EQ(ran.status, 0) << ran.err;

  // The job's 3 runs: one more run of 8 fits; the estimate from the file's 16 fits.
  const Outcome grown = validate({"--resume", "-j", "2"});
  EXPECT_EQ(grown.status, 0) << grown.err;
  EXPECT_TRUE(contains(grown.out,
                       "ggk run --resume would keep 2 complete runs, compute 1 run (8 fits) "
                       "(the job grows the file's)"));
  EXPECT_TRUE(contains(grown.out, "at the file's mean fit time ("));
  EXPECT_TRUE(contains(grown.out, " over 16 fits): about "));
  EXPECT_TRUE(contains(grown.out, " at -j 2; the runs' samples and graphs come on top"));

  // A new kernel count: the complete runs grow by its fits (2 bases x 2 solvers).
  const Outcome values = validate({"--resume", "--sweep", "kernels=4,6,8"});
  EXPECT_EQ(values.status, 0) << values.err;
  EXPECT_TRUE(contains(values.out,
                       "would keep 0 complete runs, compute 1 run (12 fits) and grow 2 complete "
                       "runs by 8 fits of the job's new values"));

  // The file's own job: nothing to compute.
  const Outcome same = validate({"--resume", "--set", "runs=2"});
  EXPECT_EQ(same.status, 0) << same.err;
  EXPECT_TRUE(
      contains(same.out, "ggk run --resume would compute nothing: its 2 runs are complete"));

  // Without --resume: run would refuse the existing output, and validate says so.
  const Outcome plain = validate({"--set", "runs=2"});
  EXPECT_EQ(plain.status, 0) << plain.err;
  EXPECT_TRUE(contains(plain.out,
                       "exists: ggk run refuses it unless --resume (continue it) or "
                       "--overwrite (replace it, deleting its runs)"));
}

TEST_F(ResumePreviewCli, RefusesWithResumeWhatRunWouldRefuse) {
  ASSERT_EQ(ggk({"run", job_.string(), "-q", "--set", "runs=2", "-o", output_.string()}).status, 0);
  const std::string bytes = file_bytes(output_);
  // Another job's file (a run-level key changed): run --resume refuses it, exit 2.
  const Outcome refused = validate({"--resume", "--set", "maze.slip=0.3"});
  EXPECT_EQ(refused.status, kUserError) << refused.out;
  EXPECT_TRUE(contains(refused.err, "cannot resume " + output_.string()));
  EXPECT_TRUE(contains(refused.err, "maze.slip"));
  const Outcome run_refused = ggk(
      {"run", job_.string(), "-q", "--resume", "--set", "maze.slip=0.3", "-o", output_.string()});
  EXPECT_EQ(run_refused.status, kUserError);
  EXPECT_TRUE(contains(run_refused.err, "cannot resume " + output_.string()));
  // Without --resume: a note, exit 0.
  const Outcome noted = validate({"--set", "maze.slip=0.3"});
  EXPECT_EQ(noted.status, 0) << noted.err;
  EXPECT_TRUE(contains(noted.out, "ggk run --resume would refuse it: cannot resume"));
  // Fewer runs than the file holds.
  const Outcome fewer = validate({"--resume", "--set", "runs=1"});
  EXPECT_EQ(fewer.status, kUserError);
  EXPECT_TRUE(contains(fewer.err, "resuming would drop runs 1..1"));
  EXPECT_EQ(file_bytes(output_), bytes);  // validate writes nothing
  // --overwrite: said, nothing read.
  const Outcome overwrite = validate({"--overwrite"});
  EXPECT_EQ(overwrite.status, 0);
  EXPECT_TRUE(contains(overwrite.out, "ggk run --overwrite would replace it (deleting its runs)"));
  EXPECT_EQ(validate({"--overwrite", "--resume"}).status, kUserError);
}

TEST_F(ResumePreviewCli, PrintShowsTheResolvedJobWhichReadsBackAsTheSameJob) {
  const Outcome printed = validate({"--print"});
  ASSERT_EQ(printed.status, 0) << printed.err;
  EXPECT_TRUE(contains(printed.out, "\n[maze]\n"));
  EXPECT_TRUE(contains(printed.out, "slip = 0.2\n"));
  EXPECT_TRUE(contains(printed.out, "\n[lspi]\n"));         // every default filled in
  EXPECT_TRUE(contains(printed.out, "max_iterations = "));  // a default of [lspi]
  EXPECT_TRUE(contains(printed.out, "kernels = [4, 8]\n"));
  const fs::path copy = write_file(dir_ / "printed.toml", printed.out);
  const Outcome again = ggk({"validate", copy.string(), "--print"});
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(again.out, printed.out);

  // A study (a swept key and a zipped pair) reads back as the same study.
  const fs::path study =
      write_file(dir_ / "study.toml", determinism_job(output_) +
                                          "[[sweep.zip]]\n\"maze.series\" = [4, 6]\n"
                                          "\"maze.steps_per_series\" = [60, 80]\n");
  const Outcome study_printed =
      ggk({"validate", study.string(), "--print", "--sweep", "maze.slip=0.0,0.2"});
  ASSERT_EQ(study_printed.status, 0) << study_printed.err;
  EXPECT_TRUE(contains(study_printed.out, "\"maze.slip\" = [0.0, 0.2]\n"));
  EXPECT_TRUE(contains(study_printed.out,
                       "[[sweep.zip]]\n\"maze.series\" = [4, 6]\n\"maze.steps_per_series\" = "
                       "[60, 80]\n"));
  const fs::path study_copy = write_file(dir_ / "study-printed.toml", study_printed.out);
  const Outcome study_again = ggk({"validate", study_copy.string(), "--print"});
  ASSERT_EQ(study_again.status, 0) << study_again.err;
  EXPECT_EQ(study_again.out, study_printed.out);

  // The printed job computes the same results as the job file.
  ASSERT_EQ(
      ggk({"run", job_.string(), "-q", "--set", "runs=1", "-o", (dir_ / "a.h5").string()}).status,
      0);
  ASSERT_EQ(
      ggk({"run", copy.string(), "-q", "--set", "runs=1", "-o", (dir_ / "b.h5").string()}).status,
      0);
  const Outcome diff = ggk({"diff", (dir_ / "a.h5").string(), (dir_ / "b.h5").string()});
  EXPECT_EQ(diff.status, 0) << diff.out;
  EXPECT_TRUE(contains(diff.out, "same results"));
}

}  // namespace
}  // namespace ggk::engine
