#pragma once
// Results files compared bit for bit, as gtest expectations (the C++ side of
// `ggk diff`, for tests that also check what the files hold).

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/job_spec.hpp"

namespace ggk::test_support {

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Same variant alternative and same value; doubles by their bits (NaN == NaN).
bool same_cell(const engine::TableValue& a, const engine::TableValue& b);
std::string cell_text(const engine::TableValue& v);

// Tables equal cell by cell, except the columns named in `skip`.
void expect_same_table(const engine::Hdf5File& a, const engine::Hdf5File& b,
                       const std::string& path,
                       const std::set<std::string>& skip = {"fit_seconds"});

// Every deterministic number of every run of `job` (complete in both files):
// fit_metrics (bar fit_seconds), each fit's arrays and status, the samples and
// the graph; and the summary.
void expect_identical_results(const engine::JobSpec& job, const std::filesystem::path& path_a,
                              const std::filesystem::path& path_b);

// (run, sweep_point) of every summary row, in order.
std::vector<std::pair<std::int32_t, std::int32_t>> summary_keys(const std::filesystem::path& path,
                                                                const std::string& task);
// (run, sweep_point) of every fit of `job`, run by run: the keys of a whole summary.
std::vector<std::pair<std::int32_t, std::int32_t>> every_fit_once(const engine::JobSpec& job);

}  // namespace ggk::test_support
