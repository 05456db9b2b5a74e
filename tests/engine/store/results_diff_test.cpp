// ggk diff (engine/store/results_diff.hpp): two runs of one job are the same
// results (wall-clock times and provenance aside); a changed value, attribute or
// missing object is a difference named by its path; a file that is no results
// file is a UsageError.

#include "engine/store/results_diff.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/job_runner.hpp"
#include "support/determinism_job.hpp"
#include "support/ggk_binary.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

constexpr const char* kWeights = "/maze/run_001/fits/ggk/k_0008_sigma3_brm_lambda1e-06/weights";

class ResultsDiffTest : public JobRunnerTest {
 protected:
  void SetUp() override {
    JobRunnerTest::SetUp();
    job_ = load_job("job.toml", determinism_job(dir_ / "a.h5"));
    run_job(job_, options_for(dir_ / "a.h5"));
    fs::copy_file(dir_ / "a.h5", dir_ / "b.h5");
  }

  // diff_results(a.h5, b.h5): the verdict and what it printed.
  std::pair<bool, std::string> diff(const DiffOptions& options = {}) const {
    std::ostringstream out;
    const bool same = diff_results(dir_ / "a.h5", dir_ / "b.h5", out, options);
    return {same, out.str()};
  }

  JobSpec job_;
};

// Replaces the dataset at `path` with `values`, keeping its string attributes
// (dims, units, description): only the values differ.
void rewrite_vector(Hdf5File& file, const std::string& path, const std::vector<double>& values) {
  std::vector<std::pair<std::string, std::string>> attributes;
  for (const std::string& name : file.attribute_names(path)) {
    attributes.emplace_back(name, file.read_string_attribute(path, name));
  }
  file.remove(path);
  file.write_vector(path, values);
  for (const auto& attribute : attributes) {
    file.write_string_attribute(path, attribute.first, attribute.second);
  }
}

TEST_F(ResultsDiffTest, TwoRunsOfOneJobAreTheSameResults) {
  // Another run, on another thread count: fit_seconds and created differ.
  fs::remove(dir_ / "b.h5");
  run_job(job_, options_for(dir_ / "b.h5", 1));
  ASSERT_NE(Hdf5File::open_read_only(dir_ / "a.h5").read_vector<double>(kWeights).size(), 0u);
  const auto [same, printed] = diff();
  EXPECT_TRUE(same) << printed;
  EXPECT_TRUE(contains(printed, "same results: "));
  EXPECT_EQ(printed.find("differs"), std::string::npos) << printed;
}

TEST_F(ResultsDiffTest, AChangedDatasetIsNamed) {
  {
    Hdf5File b = Hdf5File::open_read_write(dir_ / "b.h5");
    std::vector<double> weights = b.read_vector<double>(kWeights);
    ASSERT_FALSE(weights.empty());
    weights.back() = std::nextafter(weights.back(), 1e300);  // one ulp
    rewrite_vector(b, kWeights, weights);
    b.flush();
  }
  const auto [same, printed] = diff();
  EXPECT_FALSE(same);
  EXPECT_TRUE(contains(printed, std::string("differs: ") + kWeights + ": values differ"));
  EXPECT_TRUE(contains(printed, "different results: 1 of "));
}

TEST_F(ResultsDiffTest, ATolerancePassesWhatDiffersByLessAndSaysByHowMuch) {
  double old_value = 0.0, new_value = 0.0;
  std::size_t last = 0;
  {
    Hdf5File b = Hdf5File::open_read_write(dir_ / "b.h5");
    std::vector<double> weights = b.read_vector<double>(kWeights);
    ASSERT_FALSE(weights.empty());
    last = weights.size() - 1;
    old_value = weights.back();
    weights.back() *= 1.0 + 1e-9;
    new_value = weights.back();
    rewrite_vector(b, kWeights, weights);
    b.flush();
  }
  ASSERT_NE(old_value, new_value);
  // Bit for bit it differs, and the line says where and by how much.
  const auto [same, printed] = diff();
  EXPECT_FALSE(same);
  EXPECT_TRUE(contains(printed, std::string("differs: ") + kWeights + ": values differ: 1 of "))
      << printed;
  EXPECT_TRUE(contains(printed, "largest absolute difference ")) << printed;
  EXPECT_TRUE(contains(printed, " at [" + std::to_string(last) + "]")) << printed;
  // Within rtol 1e-8 it is the same results, with the difference reported.
  DiffOptions loose;
  loose.tolerance.rtol = 1e-8;
  const auto [same_within, within_text] = diff(loose);
  EXPECT_TRUE(same_within) << within_text;
  EXPECT_TRUE(contains(within_text, "same results within rtol 1e-08, atol 0: ")) << within_text;
  EXPECT_TRUE(contains(within_text,
                       "1 of them differ bit for bit, within the tolerance: largest "
                       "absolute difference "))
      << within_text;
  EXPECT_TRUE(contains(within_text, std::string(kWeights) + " [" + std::to_string(last) + "]"))
      << within_text;
  // rtol 1e-10 is tighter than the change.
  DiffOptions tight;
  tight.tolerance.rtol = 1e-10;
  EXPECT_FALSE(diff(tight).first);
  // Excluding the dataset leaves nothing that differs.
  DiffOptions exclude;
  exclude.exclude = {"*/k_0008_sigma3_brm_*/weights"};
  const auto [same_excluded, excluded_text] = diff(exclude);
  EXPECT_TRUE(same_excluded) << excluded_text;
  EXPECT_TRUE(contains(excluded_text, "objects excluded (--exclude)")) << excluded_text;
}

TEST_F(ResultsDiffTest, FilesOfTwoTasksAreAUsageErrorNamingBoth) {
  {
    Hdf5File b = Hdf5File::open_read_write(dir_ / "b.h5");
    b.remove_attribute("/", "task");
    b.write_string_attribute("/", "task", "arm");
    b.flush();
  }
  try {
    (void)diff();
    FAIL() << "expected a UsageError";
  } catch (const UsageError& error) {
    EXPECT_TRUE(contains(error.what(), (dir_ / "a.h5").string() + " holds maze results"))
        << error.what();
    EXPECT_TRUE(contains(error.what(), (dir_ / "b.h5").string() + " arm results")) << error.what();
  }
  DiffOptions negative;
  negative.tolerance.atol = -1.0;
  fs::copy_file(dir_ / "a.h5", dir_ / "b.h5", fs::copy_options::overwrite_existing);
  EXPECT_THROW((void)diff(negative), UsageError);
}

TEST_F(ResultsDiffTest, AChangedAttributeAndAMissingGroupAreNamed) {
  const std::string fit = "/maze/run_002/fits/ogk/k_0004_sigma3_lstdq_lambda1e-06";
  {
    Hdf5File b = Hdf5File::open_read_write(dir_ / "b.h5");
    const std::string status = b.read_string_attribute(fit, "status");
    b.remove_attribute(fit, "status");
    b.write_string_attribute(fit, "status", status == "converged" ? "max_iterations" : "converged");
    b.remove("/maze/run_000/graph");
    b.flush();
  }
  const auto [same, printed] = diff();
  EXPECT_FALSE(same);
  EXPECT_TRUE(contains(printed, "differs: " + fit + " @status: attribute differs"));
  EXPECT_TRUE(contains(printed, "differs: /maze/run_000/graph: only in the first file"));
}

TEST_F(ResultsDiffTest, ProvenanceIsANoteNotADifference) {
  {
    Hdf5File b = Hdf5File::open_read_write(dir_ / "b.h5");
    b.remove_attribute("/", "ggk_version");
    b.write_string_attribute("/", "ggk_version", "0.0.0-elsewhere");
    b.flush();
  }
  const auto [same, printed] = diff();
  EXPECT_TRUE(same) << printed;
  EXPECT_TRUE(contains(printed, "note: ggk_version: "));
  EXPECT_TRUE(contains(printed, "\"0.0.0-elsewhere\""));
}

TEST_F(ResultsDiffTest, ADifferentBlasIsNamedByItsKernelSetAndExplained) {
  const std::string prefix = "OpenBLAS 0.3.21 NO_LAPACKE DYNAMIC_ARCH NO_AFFINITY ";
  for (const auto& [file, core] : {std::pair{"a.h5", "Zen"}, std::pair{"b.h5", "SandyBridge"}}) {
    Hdf5File f = Hdf5File::open_read_write(dir_ / file);
    if (f.has_attribute("/", "blas")) f.remove_attribute("/", "blas");
    f.write_string_attribute("/", "blas", prefix + core + " MAX_THREADS=64 (pthread build)");
    f.flush();
  }
  const auto [same, printed] = diff();
  EXPECT_TRUE(same) << printed;
  // The kernel sets themselves, not a cut at the shared prefix.
  EXPECT_TRUE(contains(printed, "Zen MAX_THREADS")) << printed;
  EXPECT_TRUE(contains(printed, "SandyBridge MAX_THREADS")) << printed;
  EXPECT_TRUE(contains(printed, "bit-identical for one BLAS kernel set")) << printed;
}

// Issue 37, F8: a hostile task name is cut in the refusal (it was printed whole).
TEST_F(ResultsDiffTest, FilesOfTwoTasksAreRefusedWithTheNamesCut) {
  {
    Hdf5File b = Hdf5File::open_read_write(dir_ / "b.h5");
    b.remove_attribute("/", "task");
    b.write_string_attribute("/", "task", std::string(8'000'000, 'x'));
    b.flush();
  }
  std::ostringstream out;
  try {
    diff_results(dir_ / "a.h5", dir_ / "b.h5", out);
    FAIL() << "expected a UsageError";
  } catch (const UsageError& error) {
    EXPECT_LT(std::string(error.what()).size(), 600u);
    EXPECT_TRUE(contains(error.what(), "(8000000 bytes) results"));
  }
}

TEST_F(ResultsDiffTest, AFileThatIsNoResultsFileIsAUsageError) {
  {
    Hdf5File other = Hdf5File::create(dir_ / "other.h5");
    other.write_vector("/x", std::vector<double>{1.0});
    other.flush();
  }
  std::ostringstream out;
  try {
    diff_results(dir_ / "a.h5", dir_ / "other.h5", out);
    FAIL() << "expected a UsageError";
  } catch (const UsageError& error) {
    EXPECT_TRUE(contains(error.what(), (dir_ / "other.h5").string()));
    EXPECT_TRUE(contains(error.what(), "not a ggk results file"));
  }
  write_file(dir_ / "plain.h5", "not HDF5\n");
  EXPECT_THROW(diff_results(dir_ / "plain.h5", dir_ / "a.h5", out), UsageError);
}

// ggk diff of two studies of one job with other values of an axis: matched by
// value, the points both hold are the same results; --common compares only them.
class DiffByValue : public GgkBinaryTest {
 protected:
  void SetUp() override {
    GgkBinaryTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    job_ = write_file(dir_ / "job.toml", determinism_job(dir_ / "unused.h5"));
  }

  // The job with `options` (--set / --sweep ...) into dir_/name.
  void run(const std::string& name, std::vector<std::string> options) const {
    std::vector<std::string> args = {"run", job_.string(),          "-q",    "-j",    "2",
                                     "-o",  (dir_ / name).string(), "--set", "runs=2"};
    args.insert(args.end(), options.begin(), options.end());
    const Outcome ran = ggk(args);
    ASSERT_EQ(ran.status, 0) << ran.err;
  }

  Outcome diff(const std::string& a, const std::string& b, bool common = false) const {
    std::vector<std::string> args = {"diff", (dir_ / a).string(), (dir_ / b).string()};
    if (common) args.emplace_back("--common");
    return ggk(args);
  }

  fs::path job_;
};

// Every "differs:" line of `printed`.
std::vector<std::string> differing_lines(const std::string& printed) {
  std::vector<std::string> lines;
  std::istringstream in(printed);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("differs: ", 0) == 0) lines.push_back(line);
  }
  return lines;
}

TEST_F(DiffByValue, StudiesWithMoreValuesShareTheirCommonPoints) {
  run("two.h5", {"--sweep", "maze.slip=0.0,0.2"});
  run("three.h5", {"--sweep", "maze.slip=0.0,0.1,0.2"});
  // Without --common: what only the larger study holds is the only difference.
  const Outcome plain = diff("two.h5", "three.h5");
  EXPECT_EQ(plain.status, 1) << plain.out;
  EXPECT_TRUE(contains(plain.out,
                       "note: the jobs differ in 1 key: maze.slip: [0.0, 0.2] in the first file, "
                       "[0.0, 0.1, 0.2] in the second file"));
  const std::vector<std::string> lines = differing_lines(plain.out);
  ASSERT_FALSE(lines.empty());
  for (const std::string& line : lines) {
    EXPECT_TRUE(contains(line, "only in the second file")) << line;
    EXPECT_TRUE(contains(line, "maze.slip = 0.1")) << line;
  }
  EXPECT_TRUE(contains(plain.out, "--common compares what both hold"));
  // --common: the shared configurations (slip 0.0 and 0.2) are the same results.
  const Outcome common = diff("two.h5", "three.h5", true);
  EXPECT_EQ(common.status, 0) << common.out;
  EXPECT_TRUE(contains(common.out, "same results: "));
  EXPECT_TRUE(contains(common.out, "only in one file, not compared (--common)"));

  // A fit-level axis with one more value: the runs' shared fits are the same.
  run("k2.h5", {"--sweep", "kernels=4,8"});
  run("k3.h5", {"--sweep", "kernels=4,6,8"});
  EXPECT_EQ(diff("k2.h5", "k3.h5").status, 1);
  const Outcome kernels = diff("k3.h5", "k2.h5", true);
  EXPECT_EQ(kernels.status, 0) << kernels.out;
}

TEST_F(DiffByValue, ResultsThatDifferAtASharedPointAreStillADifference) {
  run("two.h5", {"--sweep", "maze.slip=0.0,0.2"});
  // The same slips with shorter tests: other metrics at every shared point.
  run("short.h5", {"--sweep", "maze.slip=0.0,0.1,0.2", "--set", "maze.test_max_steps=3"});
  const Outcome common = diff("two.h5", "short.h5", true);
  EXPECT_EQ(common.status, 1) << common.out;
  EXPECT_TRUE(contains(common.out, "note: the jobs differ in 2 keys: "));
  EXPECT_TRUE(contains(common.out, "maze.test_max_steps: 40 in the first file, 3 in the second"));
  EXPECT_TRUE(contains(common.out, "rows matched by their point differ"));
}

}  // namespace
}  // namespace ggk::engine
