// ggk verify (engine/store/results_verify.hpp): a whole file reads back; one
// byte flipped inside a dataset's stored chunk (found with H5Dget_chunk_info) is
// damage that verify_results and verify_run name by path; other runs stay whole.

#include "engine/store/results_verify.hpp"
#include "engine/store/run_digest.hpp"

#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/job_runner.hpp"
#include "support/chunk_damage.hpp"
#include "support/determinism_job.hpp"
#include "support/ggk_binary.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

constexpr const char* kWeightsDataset =
    "/maze/run_001/fits/ggk/k_0008_sigma3_brm_lambda1e-06/weights";

class ResultsVerifyTest : public JobRunnerTest {
 protected:
  void SetUp() override {
    JobRunnerTest::SetUp();
    const JobSpec job = load_job("job.toml", determinism_job(dir_ / "out.h5"));
    run_job(job, options_for(dir_ / "out.h5"));
  }

  std::pair<bool, std::string> verify() const {
    std::ostringstream out;
    const bool whole = verify_results(dir_ / "out.h5", out);
    return {whole, out.str()};
  }
};

TEST_F(ResultsVerifyTest, AWholeFileReadsBack) {
  const auto [whole, printed] = verify();
  EXPECT_TRUE(whole) << printed;
  EXPECT_TRUE(contains(printed, "runs: 3 of 3 complete"));
  EXPECT_TRUE(contains(printed, "ok: every checksum matches"));
  const Hdf5File file = Hdf5File::open_read_only(dir_ / "out.h5");
  for (std::int32_t run = 0; run < 3; ++run) {
    EXPECT_EQ(verify_run(file, "maze", run), std::nullopt) << "run " << run;
  }
}

TEST_F(ResultsVerifyTest, AFlippedByteInAChunkIsFoundAndNamed) {
  const ChunkPlace chunk = first_chunk(dir_ / "out.h5", kWeightsDataset);
  ASSERT_NE(chunk.address, HADDR_UNDEF) << "no chunk found for " << kWeightsDataset;
  ASSERT_GT(chunk.size, 4u);
  flip_byte(dir_ / "out.h5", chunk.address + chunk.size / 2);

  const auto [whole, printed] = verify();
  EXPECT_FALSE(whole) << printed;
  EXPECT_TRUE(contains(printed, "DAMAGED: 1 objects do not read:"));
  EXPECT_TRUE(contains(printed, std::string("  ") + kWeightsDataset + ": "));
  EXPECT_TRUE(contains(printed, "--resume"));

  const Hdf5File file = Hdf5File::open_read_only(dir_ / "out.h5");
  const std::optional<std::string> damage = verify_run(file, "maze", 1);
  ASSERT_TRUE(damage.has_value());
  EXPECT_TRUE(contains(*damage, kWeightsDataset));
  EXPECT_EQ(verify_run(file, "maze", 0), std::nullopt);
  EXPECT_EQ(verify_run(file, "maze", 2), std::nullopt);
}

// Links no results file holds, made with the C API: a hard link from a run to
// an ancestor (a cycle), an external link to the file itself, groups nested
// 2,000 deep. The walks of verify_results and verify_run (what --resume reads)
// end on each, naming the object; before, the first two never ended.
void add_link(const fs::path& path, const std::string& kind) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  if (kind == "ancestor") {
    EXPECT_GE(H5Lcreate_hard(f, "/maze", f, "/maze/run_001/loop", H5P_DEFAULT, H5P_DEFAULT), 0);
  } else if (kind == "self") {
    EXPECT_GE(
        H5Lcreate_external(path.c_str(), "/", f, "/maze/run_001/self", H5P_DEFAULT, H5P_DEFAULT),
        0);
  } else {
    std::string group = "/maze/run_001";
    for (int depth = 0; depth < 2000; ++depth) {
      group += "/n";
      const hid_t g = H5Gcreate2(f, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      ASSERT_GE(g, 0);
      H5Gclose(g);
    }
  }
  H5Fclose(f);
}

TEST_F(ResultsVerifyTest, CyclesExternalLinksAndDeepNestingEndAndAreNamed) {
  for (const std::string kind : {"ancestor", "self", "deep"}) {
    const fs::path path = dir_ / (kind + ".h5");
    fs::copy_file(dir_ / "out.h5", path);
    add_link(path, kind);
    std::ostringstream out;
    EXPECT_FALSE(verify_results(path, out)) << kind;
    EXPECT_TRUE(contains(out.str(), "/maze/run_001/")) << kind << ": " << out.str();
    const Hdf5File file = Hdf5File::open_read_only(path);
    const std::optional<std::string> damage = verify_run(file, "maze", 1);
    ASSERT_TRUE(damage.has_value()) << kind;
    EXPECT_TRUE(contains(*damage, kind == "ancestor" ? "linked a second time"
                                  : kind == "self"   ? "soft or external link"
                                                     : "nested deeper"))
        << *damage;
    EXPECT_EQ(verify_run(file, "maze", 0), std::nullopt) << kind;
  }
}

// Objects that all read can still make a run that is not whole: its fits
// group deleted, its actions replaced by another shape. verify_results and
// verify_run (so --resume, which then computes it again) name it; before,
// verify exited 0 and --resume kept the run.
TEST_F(ResultsVerifyTest, ARunCutOrReplacedIsNotWhole) {
  {
    Hdf5File file = Hdf5File::open_read_write(dir_ / "out.h5");
    file.remove("/maze/run_001/fits");
    file.remove("/maze/run_002/samples/actions");
    file.write_matrix("/maze/run_002/samples/actions", 2, 2, std::vector<std::int32_t>(4, 0));
    file.flush();
  }
  const auto [whole, printed] = verify();
  EXPECT_FALSE(whole) << printed;
  EXPECT_TRUE(contains(printed, "/maze/run_001/fits: 0 fit groups")) << printed;
  EXPECT_TRUE(contains(printed, "/maze/run_002/samples/actions: not a vector")) << printed;
  const Hdf5File file = Hdf5File::open_read_only(dir_ / "out.h5");
  EXPECT_NE(verify_run(file, "maze", 1), std::nullopt);
  EXPECT_NE(verify_run(file, "maze", 2), std::nullopt);
  EXPECT_EQ(verify_run(file, "maze", 0), std::nullopt);
}

// Object headers carry no checksum in the format ggk writes: a renamed
// attribute, an attribute's changed value or a renamed dataset read back
// without error. The run's digest finds them; a wall-clock attribute is not
// part of it.
TEST_F(ResultsVerifyTest, ChangesNoChecksumCoversDifferFromTheRunsDigest) {
  const std::string fit = "/maze/run_001/fits/ggk/k_0008_sigma3_brm_lambda1e-06";
  {
    Hdf5File file = Hdf5File::open_read_write(dir_ / "out.h5");
    ASSERT_TRUE(file.has_attribute("/maze/run_000", kRunDigestAttribute));
    ASSERT_TRUE(file.has_attribute(fit, "fit_seconds"));
    file.remove_attribute(fit, "fit_seconds");  // wall clock: not in the digest
    file.write_double_attribute(fit, "fit_seconds", 1234.5);
    const std::string renamed = "/maze/run_000/fits/ggk/k_0008_sigma3_brm_lambda1e-06";
    const double stretch = file.read_double_attribute(renamed, "geodesic_stretch");
    file.remove_attribute(renamed, "geodesic_stretch");
    file.write_double_attribute(renamed, "geodesic_strftch", stretch);
    const std::int64_t complete = file.read_int64_attribute("/maze/run_002", "complete");
    file.move("/maze/run_002/samples/rewards", "/maze/run_002/samples/rewardz");
    file.remove_attribute("/maze/run_002", "complete");  // (complete: not in the digest)
    file.write_int64_attribute("/maze/run_002", "complete", complete);
    file.flush();
  }
  const Hdf5File file = Hdf5File::open_read_only(dir_ / "out.h5");
  EXPECT_EQ(verify_run(file, "maze", 1), std::nullopt);
  const std::optional<std::string> renamed = verify_run(file, "maze", 0);
  ASSERT_NE(renamed, std::nullopt);
  EXPECT_TRUE(contains(*renamed, "/maze/run_000: its names, attributes, shapes or values differ"));
  EXPECT_NE(verify_run(file, "maze", 2), std::nullopt);
  const auto [whole, printed] = verify();
  EXPECT_FALSE(whole) << printed;
  EXPECT_TRUE(contains(printed, "/maze/run_000: its names, attributes, shapes or values differ"));
}

TEST_F(ResultsVerifyTest, AFileThatIsNoResultsFileIsAUsageError) {
  std::ostringstream out;
  EXPECT_THROW(verify_results(dir_ / "missing.h5", out), UsageError);
  write_file(dir_ / "plain.h5", "not HDF5\n");
  EXPECT_THROW(verify_results(dir_ / "plain.h5", out), UsageError);
  {
    Hdf5File other = Hdf5File::create(dir_ / "other.h5");
    other.write_vector("/x", std::vector<double>{1.0});
    other.flush();
  }
  try {
    verify_results(dir_ / "other.h5", out);
    FAIL() << "expected a UsageError";
  } catch (const UsageError& error) {
    EXPECT_TRUE(contains(error.what(), "not a ggk results file"));
  }
}

}  // namespace
}  // namespace ggk::engine
