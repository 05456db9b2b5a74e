#include "support/results_compare.hpp"

#include <bit>
#include <type_traits>
#include <variant>

#include <gtest/gtest.h>

#include "engine/job/sweep.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::test_support {

namespace fs = std::filesystem;
using engine::Hdf5File;
using engine::TableColumn;
using engine::TableRow;
using engine::TableValue;

bool same_cell(const TableValue& a, const TableValue& b) {
  if (a.index() != b.index()) return false;
  if (const auto* x = std::get_if<double>(&a)) {
    return std::bit_cast<std::uint64_t>(*x) == std::bit_cast<std::uint64_t>(std::get<double>(b));
  }
  return a == b;
}

std::string cell_text(const TableValue& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::string>) {
          return "\"" + x + "\"";
        } else {
          return std::to_string(x);
        }
      },
      v);
}

void expect_same_table(const Hdf5File& a, const Hdf5File& b, const std::string& path,
                       const std::set<std::string>& skip) {
  SCOPED_TRACE(path);
  const std::vector<TableColumn> columns = a.read_table_columns(path);
  ASSERT_EQ(columns, b.read_table_columns(path));
  const std::vector<TableRow> rows_a = a.read_table(path);
  const std::vector<TableRow> rows_b = b.read_table(path);
  ASSERT_EQ(rows_a.size(), rows_b.size());
  for (std::size_t r = 0; r < rows_a.size(); ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (skip.contains(columns[c].name)) continue;
      EXPECT_TRUE(same_cell(rows_a[r][c], rows_b[r][c]))
          << "row " << r << ", column " << columns[c].name << ": " << cell_text(rows_a[r][c])
          << " vs " << cell_text(rows_b[r][c]);
    }
  }
}

namespace {

template <class T>
void expect_same_vector(const Hdf5File& a, const Hdf5File& b, const std::string& path) {
  ASSERT_EQ(a.exists(path), b.exists(path)) << path;
  if (!a.exists(path)) return;
  EXPECT_TRUE(same_bits(a.read_vector<T>(path), b.read_vector<T>(path))) << path;
}

void expect_same_matrix(const Hdf5File& a, const Hdf5File& b, const std::string& path) {
  const engine::RowMajorArray<double> x = a.read_matrix<double>(path);
  const engine::RowMajorArray<double> y = b.read_matrix<double>(path);
  EXPECT_EQ(x.rows, y.rows) << path;
  EXPECT_EQ(x.cols, y.cols) << path;
  EXPECT_TRUE(same_bits(x.data, y.data)) << path;
}

}  // namespace

void expect_identical_results(const engine::JobSpec& job, const fs::path& path_a,
                              const fs::path& path_b) {
  const Hdf5File a = Hdf5File::open_read_only(path_a);
  const Hdf5File b = Hdf5File::open_read_only(path_b);
  const std::vector<engine::SweepPoint> points = engine::expand_sweep(job);
  for (std::int32_t run = 0; run < job.runs; ++run) {
    const std::string group = engine::run_group(job.task, run);
    SCOPED_TRACE(group);
    ASSERT_TRUE(engine::run_is_complete(a, job.task, run));
    ASSERT_TRUE(engine::run_is_complete(b, job.task, run));
    expect_same_table(a, b, group + "/fit_metrics");
    for (const engine::SweepPoint& point : points) {
      const std::string fit = group + "/fits/" + engine::fit_group_name(job, point);
      SCOPED_TRACE(fit);
      EXPECT_EQ(a.read_string_attribute(fit, "status"), b.read_string_attribute(fit, "status"));
      expect_same_vector<std::int32_t>(a, b, fit + "/centers");
      expect_same_vector<double>(a, b, fit + "/weights");
      expect_same_vector<std::int32_t>(a, b, fit + "/policy");
      expect_same_vector<std::int32_t>(a, b, fit + "/steps_to_goal");
      expect_same_vector<double>(a, b, fit + "/state_values");
      expect_same_vector<std::int32_t>(a, b, fit + "/history/policy_changes");
      expect_same_vector<double>(a, b, fit + "/history/relative_residual");
      expect_same_vector<double>(a, b, fit + "/history/rcond");
    }
    const std::string samples = group + "/samples";
    expect_same_matrix(a, b, samples + "/observations");
    expect_same_vector<std::int32_t>(a, b, samples + "/actions");
    expect_same_vector<double>(a, b, samples + "/rewards");
    expect_same_matrix(a, b, samples + "/next_observations");
    expect_same_vector<std::uint8_t>(a, b, samples + "/terminals");
    const std::string graph = group + "/graph";
    expect_same_vector<std::int64_t>(a, b, graph + "/indptr");
    expect_same_vector<std::int32_t>(a, b, graph + "/indices");
    expect_same_vector<double>(a, b, graph + "/weights");
    expect_same_matrix(a, b, graph + "/nodes");
  }
  expect_same_table(a, b, "/" + job.task + "/summary");
}

std::vector<std::pair<std::int32_t, std::int32_t>> summary_keys(const fs::path& path,
                                                                const std::string& task) {
  const Hdf5File file = Hdf5File::open_read_only(path);
  std::vector<std::pair<std::int32_t, std::int32_t>> keys;
  for (const TableRow& row : file.read_table("/" + task + "/summary")) {
    keys.emplace_back(std::get<std::int32_t>(row.at(0)), std::get<std::int32_t>(row.at(1)));
  }
  return keys;
}

std::vector<std::pair<std::int32_t, std::int32_t>> every_fit_once(const engine::JobSpec& job) {
  std::vector<std::pair<std::int32_t, std::int32_t>> keys;
  const auto points = static_cast<std::int32_t>(engine::expand_sweep(job).size());
  for (std::int32_t run = 0; run < job.runs; ++run) {
    for (std::int32_t p = 0; p < points; ++p) keys.emplace_back(run, p);
  }
  return keys;
}

}  // namespace ggk::test_support
