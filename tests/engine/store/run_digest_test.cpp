// A run's digest (engine/store/run_digest.hpp): what it covers and leaves out.
// That verify finds a changed digest: results_verify_test.cpp.

#include "engine/store/run_digest.hpp"

#include <gtest/gtest.h>

#include "engine/run/job_runner.hpp"
#include "engine/store/run_store.hpp"
#include "support/determinism_job.hpp"

namespace ggk::engine {
namespace {

using namespace test_support;

TEST_F(JobRunnerTest, ARunsDigestCoversNamesAttributesShapesAndValues) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "out.h5"));
  run_job(job, options_for(job.output.file));
  const std::string run = "/maze/run_000";
  const std::string fit = run + "/fits/ggk/k_0008_sigma3_brm_lambda1e-06";
  Hdf5File file = Hdf5File::open_read_write(job.output.file);
  const std::uint64_t stored =
      static_cast<std::uint64_t>(file.read_int64_attribute(run, kRunDigestAttribute));
  EXPECT_EQ(run_digest(file, run), stored);  // as written (under /.staging, then moved)
  EXPECT_NE(run_digest(file, "/maze/run_001"), stored);

  // Left out: the wall clock (attribute and table column) and the group's own marks.
  file.remove_attribute(fit, "fit_seconds");
  file.write_double_attribute(fit, "fit_seconds", 99.0);
  file.remove_attribute(run, "complete");
  std::vector<TableRow> rows = file.read_table(run + "/fit_metrics");
  const std::vector<TableColumn> columns = file.read_table_columns(run + "/fit_metrics");
  ASSERT_EQ(columns.back().name, "fit_seconds");
  for (TableRow& row : rows) row.back() = 99.0;
  std::vector<std::pair<std::string, std::string>> attributes;  // dims, units, ...
  for (const std::string& name : file.attribute_names(run + "/fit_metrics")) {
    attributes.emplace_back(name, file.read_string_attribute(run + "/fit_metrics", name));
  }
  file.remove(run + "/fit_metrics");
  file.create_table(run + "/fit_metrics", columns);
  file.append_rows(run + "/fit_metrics", rows);
  for (const auto& [name, text] : attributes) {
    file.write_string_attribute(run + "/fit_metrics", name, text);
  }
  EXPECT_EQ(run_digest(file, run), stored);

  // Covered: an attribute's value, a name, a dataset's shape.
  const double stretch = file.read_double_attribute(fit, "geodesic_stretch");
  file.remove_attribute(fit, "geodesic_stretch");
  file.write_double_attribute(fit, "geodesic_stretch", stretch + 1.0);
  EXPECT_NE(run_digest(file, run), stored);
  file.remove_attribute(fit, "geodesic_stretch");
  file.write_double_attribute(fit, "geodesic_stretch", stretch);
  EXPECT_EQ(run_digest(file, run), stored);
  file.move(run + "/graph", run + "/graph_");
  EXPECT_NE(run_digest(file, run), stored);
  file.move(run + "/graph_", run + "/graph");
  // A dataset's values: another dataset's chunks behind the same name and shape
  // (what a damaged object header can do, every chunk checksum passing).
  const std::string weights_path = fit + "/weights";
  std::vector<std::pair<std::string, std::string>> described;  // dims, units, description
  for (const std::string& name : file.attribute_names(weights_path)) {
    described.emplace_back(name, file.read_string_attribute(weights_path, name));
  }
  const auto rewrite = [&](const std::vector<double>& values) {
    file.remove(weights_path);
    file.write_vector(weights_path, values);
    for (const auto& [name, text] : described)
      file.write_string_attribute(weights_path, name, text);
  };
  const std::vector<double> weights = file.read_vector<double>(weights_path);
  std::vector<double> other = weights;
  other.front() += 1.0;
  rewrite(other);
  EXPECT_NE(run_digest(file, run), stored);
  rewrite(weights);
  EXPECT_EQ(run_digest(file, run), stored);
  // The metadata digest of older files does not see values.
  const std::uint64_t metadata = run_digest(file, run, DigestScope::kMetadata);
  rewrite(other);
  EXPECT_EQ(run_digest(file, run, DigestScope::kMetadata), metadata);
  rewrite(std::vector<double>(weights.begin(), weights.end() - 1));
  EXPECT_NE(run_digest(file, run), stored);
  EXPECT_NE(run_digest(file, run, DigestScope::kMetadata), metadata);
}

}  // namespace
}  // namespace ggk::engine
