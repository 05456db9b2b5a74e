#include "engine/store/run_store.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>

#include "engine/store/dataset_schema.hpp"
#include "engine/store/disk_room.hpp"
#include "engine/store/metric_specs_table.hpp"
#include "engine/store/run_digest.hpp"

namespace ggk::engine {

namespace {

constexpr std::size_t kVariableLength = 0;  // string columns: variable-length UTF-8

// The shortest text that reads back as exactly `value` ("2.5", "1e-06",
// "10.000001"): distinct values always get distinct fit group names.
std::string shortest_text(double value) {
  char text[64];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

template <typename T>
std::span<const T> as_span(const std::vector<T>& v) {
  return {v.data(), v.size()};
}

// The values as integers of type T; a value that is not one (a fraction, NaN,
// out of T's range) is a bug of the task that made the array.
template <typename T>
std::vector<T> integers_of(const NamedArray& array) {
  std::vector<T> integers;
  integers.reserve(array.values.size());
  for (const double value : array.values) {
    const bool fits = value >= static_cast<double>(std::numeric_limits<T>::min()) &&
                      value <= static_cast<double>(std::numeric_limits<T>::max());
    if (!fits || value != std::trunc(value)) {
      throw std::logic_error("array '" + array.name + "' is stored as integers but holds " +
                             shortest_text(value));
    }
    integers.push_back(static_cast<T>(value));
  }
  return integers;
}

void write_named_array(Hdf5File& file, const std::string& group, const NamedArray& array) {
  const std::string path = group + "/" + array.name;
  if (array.shape.size() == 2) {
    switch (array.element_type) {
      case ElementType::kFloat64:
        file.write_matrix(path, array.shape[0], array.shape[1], as_span(array.values));
        return;
      case ElementType::kInt32:
        file.write_matrix(path, array.shape[0], array.shape[1],
                          as_span(integers_of<std::int32_t>(array)));
        return;
      case ElementType::kInt64:
      case ElementType::kUInt8:
        throw std::logic_error("array '" + array.name +
                               "': 2-D arrays are stored as float64 or int32 only");
    }
  }
  switch (array.element_type) {
    case ElementType::kFloat64:
      file.write_vector(path, as_span(array.values));
      return;
    case ElementType::kInt32:
      file.write_vector(path, as_span(integers_of<std::int32_t>(array)));
      return;
    case ElementType::kInt64:
      file.write_vector(path, as_span(integers_of<std::int64_t>(array)));
      return;
    case ElementType::kUInt8:
      file.write_vector(path, as_span(integers_of<std::uint8_t>(array)));
      return;
  }
}

void write_samples(Hdf5File& file, const std::string& group, const SampleRecord& s) {
  file.write_matrix(group + "/observations", s.observations.rows(), s.observations.cols(),
                    {s.observations.data(), static_cast<std::size_t>(s.observations.size())});
  file.write_vector(group + "/actions", as_span(s.actions));
  file.write_vector(group + "/rewards", as_span(s.rewards));
  file.write_matrix(
      group + "/next_observations", s.next_observations.rows(), s.next_observations.cols(),
      {s.next_observations.data(), static_cast<std::size_t>(s.next_observations.size())});
  file.write_vector(group + "/terminals", as_span(s.terminals));
}

void write_graph(Hdf5File& file, const std::string& group, const RunRecord& r) {
  file.write_csr(group, r.graph.num_nodes, r.graph.num_nodes, as_span(r.graph.indptr),
                 as_span(r.graph.indices), as_span(r.graph.weights), "weights");
  file.write_matrix(group + "/nodes", r.node_states.rows(), r.node_states.cols(),
                    {r.node_states.data(), static_cast<std::size_t>(r.node_states.size())});
}

// A study value (canonical TOML text) as its column's type: integers int64,
// floats float64, strings unquoted, booleans as "true" / "false".
ColumnType study_column_type(const std::string& value) {
  if (value.empty()) return ColumnType::kString;
  if (value.front() == '"' || value == "true" || value == "false") return ColumnType::kString;
  if (value.find_first_of(".eEn") != std::string::npos) return ColumnType::kFloat64;  // inf, nan
  return ColumnType::kInt64;
}

TableValue study_cell(const std::string& value) {
  switch (study_column_type(value)) {
    case ColumnType::kFloat64:
      return value == "inf" || value == "+inf"        ? std::numeric_limits<double>::infinity()
             : value == "-inf"                        ? -std::numeric_limits<double>::infinity()
             : value.find("nan") != std::string::npos ? std::numeric_limits<double>::quiet_NaN()
                                                      : std::strtod(value.c_str(), nullptr);
    case ColumnType::kInt64:
      return static_cast<std::int64_t>(std::strtoll(value.c_str(), nullptr, 10));
    default:
      return value.size() >= 2 && value.front() == '"' ? value.substr(1, value.size() - 2) : value;
  }
}

bool is_integer_metric(const RunRecord& record, const std::string& name) {
  const MetricSpec* spec = find_metric_spec(record.metric_specs, name);
  return spec != nullptr && spec->integer;
}

// The declarations of the run's fit_metrics columns after status: the task's
// (an undeclared one, of a record built by hand, an unbounded mean without
// unit), then the fit's wall time.
std::vector<MetricSpec> declared_columns(const RunRecord& record,
                                         const std::vector<std::string>& metric_names) {
  std::vector<MetricSpec> specs;
  for (const std::string& name : metric_names) {
    const MetricSpec* spec = find_metric_spec(record.metric_specs, name);
    specs.push_back(spec != nullptr ? *spec : mean_metric(name, "", ""));
  }
  specs.push_back(fit_seconds_spec());
  return specs;
}

// An integer metric's value as int64; one that is not a whole number is a bug
// of the task that declared it.
std::int64_t whole_number(const std::string& name, double value) {
  if (!(std::trunc(value) == value && std::abs(value) < 9.0e15)) {
    throw std::logic_error("metric '" + name + "' is declared an integer but is " +
                           shortest_text(value));
  }
  return static_cast<std::int64_t>(value);
}

// `value` as a column of type `type` holds it: int32, int64 and float64 convert
// into each other when the value is exact in the target type; anything else
// is returned as it is (and refused by the table's writer).
TableValue as_column_type(TableValue value, ColumnType type) {
  const auto number = [&]() -> std::optional<double> {
    if (const auto* i = std::get_if<std::int32_t>(&value)) return *i;
    if (const auto* l = std::get_if<std::int64_t>(&value)) return static_cast<double>(*l);
    if (const auto* d = std::get_if<double>(&value)) return *d;
    return std::nullopt;
  }();
  if (!number) return value;
  const double x = *number;
  const bool whole = std::trunc(x) == x;
  switch (type) {
    case ColumnType::kFloat64:
      return x;
    case ColumnType::kInt64:
      if (whole && std::abs(x) < 9.0e15) return static_cast<std::int64_t>(x);
      return value;
    case ColumnType::kInt32:
      if (whole && x >= INT32_MIN && x <= INT32_MAX) return static_cast<std::int32_t>(x);
      return value;
    case ColumnType::kString:
      return value;
  }
  return value;
}

TableRow summary_row(const RunRecord& record, const FitRecord& fit) {
  TableRow row = {record.run, fit.point.index};
  for (TableValue& value : point_axis_cells(fit.point)) row.push_back(std::move(value));
  row.emplace_back(fit.status);
  for (const auto& [name, value] : fit.metrics) {
    if (is_integer_metric(record, name)) {
      row.emplace_back(whole_number(name, value));
    } else {
      row.emplace_back(value);
    }
  }
  row.emplace_back(fit.fit_seconds);
  return row;
}

void write_fit(Hdf5File& file, const std::string& group, const FitRecord& fit, const JobSpec& job,
               const RunRecord& record) {
  file.create_group(group);
  file.write_string_attribute(group, "basis", kernel_type_name(fit.point.basis));
  file.write_int64_attribute(group, "kernels", fit.point.kernels);
  file.write_double_attribute(group, "sigma", fit.point.sigma);
  file.write_string_attribute(group, "solver", solver_name(fit.point.solver));
  file.write_double_attribute(group, "lambda", fit.point.lambda);
  file.write_int64_attribute(group, "sweep_point", fit.point.index);
  file.write_string_attribute(group, "status", fit.status);
  file.write_string_attribute(group, "message", fit.message);
  if (!fit.warning.empty()) file.write_string_attribute(group, "warning", fit.warning);
  file.write_vector(group + "/centers", as_span(fit.centers));
  const auto& w = fit.lspi.weights;
  file.write_vector(group + "/weights",
                    std::span<const double>(w.data(), static_cast<std::size_t>(w.size())));
  file.write_vector(group + "/policy", as_span(fit.lspi.policy));
  std::vector<std::int32_t> changes;
  std::vector<double> weight_changes, residuals, rconds;
  std::vector<std::int32_t> dense_solves;
  for (const auto& it : fit.lspi.history) {
    dense_solves.push_back(it.dense_solve ? 1 : 0);
    changes.push_back(it.policy_changes);
    weight_changes.push_back(it.weight_change);
    residuals.push_back(it.relative_residual);
    rconds.push_back(it.rcond);
  }
  file.write_vector(group + "/history/policy_changes", as_span(changes));
  file.write_vector(group + "/history/weight_change", as_span(weight_changes));
  file.write_vector(group + "/history/relative_residual", as_span(residuals));
  file.write_vector(group + "/history/rcond", as_span(rconds));
  file.write_vector(group + "/history/dense_solve", as_span(dense_solves));
  for (const auto& [name, value] : fit.metrics) {
    if (is_integer_metric(record, name)) {
      file.write_int64_attribute(group, name, whole_number(name, value));
    } else {
      file.write_double_attribute(group, name, value);
    }
  }
  file.write_double_attribute(group, "fit_seconds", fit.fit_seconds);
  if (job.output.store_matrices && fit.lspi.weights.size() > 0) {
    // A as CSR (transposing the column-major system); BRM stores its lower triangle.
    const kernels::SparseRowMatrix a(fit.lspi.a);
    file.write_csr(group + "/A", a);
    file.write_vector(
        group + "/b",
        std::span<const double>(fit.lspi.b.data(), static_cast<std::size_t>(fit.lspi.b.size())));
  }
  for (const NamedArray& array : fit.arrays) write_named_array(file, group, array);
}

std::vector<std::string> metric_names_of(const RunRecord& record) {
  std::vector<std::string> names;
  if (!record.fits.empty()) {
    for (const auto& [name, value] : record.fits.front().metrics) names.push_back(name);
  }
  return names;
}

// Takes `path` out of the file's tree as far as it can without reading below
// it: detached (one reference kept, so HDF5 never walks or frees what is below:
// its space stays unused), or if not even its header reads, its link moved to a
// scratch name of the root ("/.staging_discarded_N", which readers skip),
// touching only the link. For what a failed or killed writer left, and damaged
// runs: freeing such an object reads its damaged B-trees and heaps, and after
// a full disk that fed HDF5's free-space manager sections it then failed on
// ("can't find section node on size list": the first resume failed).
void abandon(Hdf5File& file, const std::string& path) {
  try {
    file.detach(path);
    return;
  } catch (const std::runtime_error&) {
  }
  constexpr int kMaxAside = 100000;
  for (int n = 0; n < kMaxAside; ++n) {
    const std::string aside = kStagingRoot + "_discarded_" + std::to_string(n);
    if (!file.exists(aside)) {
      file.move(path, aside);
      return;
    }
  }
  throw std::runtime_error(path + " cannot be set aside: " + std::to_string(kMaxAside) +
                           " damaged objects are set aside already");
}

// Unlinks this session's own scratch at `path` and frees its space; abandons it
// when it cannot be freed.
void drop(Hdf5File& file, const std::string& path) {
  try {
    file.remove(path);
    return;
  } catch (const std::runtime_error&) {
  }
  abandon(file, path);
}

// Room a commit may need beyond the raw bytes of its data: object headers,
// B-trees, heaps, chunk index nodes.
constexpr std::uint64_t kCommitOverhead = 256 * 1024;
constexpr std::uint64_t kPerObjectOverhead = 4096;

std::uint64_t array_bytes(const NamedArray& array) {
  return array.values.size() * sizeof(double) + kPerObjectOverhead;
}

// An upper bound of what write_run can add to a file for `record`: the data
// uncompressed (every dataset is new: each chunk is written once) and the
// metadata of every object.
std::uint64_t run_bytes_bound(const JobSpec& job, const RunRecord& record) {
  const SampleRecord& s = record.samples;
  std::uint64_t bytes = (static_cast<std::uint64_t>(s.observations.size()) +
                         static_cast<std::uint64_t>(s.next_observations.size())) *
                            sizeof(double) +
                        s.actions.size() * 4 + s.rewards.size() * 8 + s.terminals.size();
  bytes += record.graph.indptr.size() * 8 + record.graph.indices.size() * 12 +
           static_cast<std::uint64_t>(record.node_states.size()) * 8;
  for (const NamedArray& array : record.arrays) bytes += array_bytes(array);
  for (const FitRecord& fit : record.fits) {
    bytes += 16 * kPerObjectOverhead + fit.centers.size() * 4 +
             static_cast<std::uint64_t>(fit.lspi.weights.size()) * 8 + fit.lspi.policy.size() * 4 +
             fit.lspi.history.size() * 24 + fit.message.size() + fit.warning.size();
    if (job.output.store_matrices) {
      bytes += static_cast<std::uint64_t>(fit.lspi.a.nonZeros()) * 12 +
               static_cast<std::uint64_t>(fit.lspi.a.rows() + fit.lspi.b.size()) * 8;
    }
    for (const NamedArray& array : fit.arrays) bytes += array_bytes(array);
  }
  return bytes + kCommitOverhead;
}

// Abandons an earlier, incomplete copy of a run and whatever a killed writer
// left at its staging path (either may be damaged, so neither is read).
void clear_run_slots(Hdf5File& file, const std::string& group, const std::string& staging) {
  if (file.exists(group)) abandon(file, group);
  if (file.exists(staging)) abandon(file, staging);
}

}  // namespace

bool is_scratch(std::string_view root_member) {
  return root_member.starts_with(std::string_view(kStagingRoot).substr(1));
}

std::string run_group(const std::string& task, std::int32_t run) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "/run_%03d", run);
  return "/" + task + buffer;
}

std::string staging_group(const std::string& task, std::int32_t run) {
  return kStagingRoot + run_group(task, run);
}

std::string fit_group_name(const SweepPoint& point) {
  // Every axis, always, in sweep order: the name of a fit does not depend on
  // which axes the job sweeps, so scripts and two jobs' files address it alike.
  char kernels[16];
  std::snprintf(kernels, sizeof kernels, "k_%04d", point.kernels);
  // Fit-level study keys (study.hpp) follow, when the job has any.
  return std::string(kernel_type_name(point.basis)) + "/" + kernels + "_sigma" +
         shortest_text(point.sigma) + "_" + std::string(solver_name(point.solver)) + "_lambda" +
         shortest_text(point.lambda) +
         (point.variant_label.empty() ? std::string() : "_" + point.variant_label);
}

std::string fit_group_name(const JobSpec& /*job*/, const SweepPoint& point) {
  return fit_group_name(point);
}

std::vector<TableColumn> summary_columns(const std::vector<std::string>& metric_names,
                                         const std::vector<std::string>& integer_metrics) {
  return summary_columns(metric_names, false, {}, integer_metrics);
}

std::vector<TableColumn> summary_columns(const std::vector<std::string>& metric_names,
                                         bool configuration,
                                         const std::vector<AxisAssignment>& study_values,
                                         const std::vector<std::string>& integer_metrics) {
  std::vector<TableColumn> columns = {{"run", ColumnType::kInt32, 0}};
  if (configuration) columns.push_back({"configuration", ColumnType::kInt32, 0});
  for (TableColumn column :
       std::vector<TableColumn>{{"sweep_point", ColumnType::kInt32, 0},
                                {"basis", ColumnType::kString, kVariableLength},
                                {"kernels", ColumnType::kInt32, 0},
                                {"sigma", ColumnType::kFloat64, 0},
                                {"solver", ColumnType::kString, kVariableLength},
                                {"lambda", ColumnType::kFloat64, 0}}) {
    columns.push_back(std::move(column));
  }
  for (const AxisAssignment& value : study_values) {
    columns.push_back({value.key, study_column_type(value.value), kVariableLength});
  }
  columns.push_back({"status", ColumnType::kString, kVariableLength});
  for (const std::string& name : metric_names) {
    const bool integer =
        std::find(integer_metrics.begin(), integer_metrics.end(), name) != integer_metrics.end();
    columns.push_back({name, integer ? ColumnType::kInt64 : ColumnType::kFloat64, 0});
  }
  columns.push_back({"fit_seconds", ColumnType::kFloat64, 0});
  return columns;
}

TableRow point_axis_cells(const SweepPoint& point) {
  TableRow row = {std::string(kernel_type_name(point.basis)), point.kernels, point.sigma,
                  std::string(solver_name(point.solver)), point.lambda};
  for (const AxisAssignment& value : point.study_values) row.push_back(study_cell(value.value));
  return row;
}

std::vector<std::string> point_axis_names(const SweepPoint& point) {
  std::vector<std::string> names = {"basis", "kernels", "sigma", "solver", "lambda"};
  for (const AxisAssignment& value : point.study_values) names.push_back(value.key);
  return names;
}

std::string runs_location(const JobSpec& job) {
  return job.configuration_group.empty() ? job.task : job.task + "/" + job.configuration_group;
}

std::string stage_run(Hdf5File& file, const JobSpec& job, const RunRecord& record) {
  const std::string location = runs_location(job);
  const std::string staging = staging_group(location, record.run);
  if (!file.in_memory()) {
    require_room(file.path(), run_bytes_bound(job, record), "run " + std::to_string(record.run));
  }
  if (file.exists(staging)) abandon(file, staging);  // a killed writer's: never read
  file.create_group(staging);
  write_samples(file, staging + "/samples", record.samples);
  write_graph(file, staging + "/graph", record);
  for (const NamedArray& array : record.arrays) write_named_array(file, staging, array);
  if (!record.action_names.empty()) {
    file.write_strings(staging + "/action_names", record.action_names);
  }
  std::vector<TableRow> rows;
  for (const FitRecord& fit : record.fits) {
    write_fit(file, staging + "/fits/" + fit_group_name(job, fit.point), fit, job, record);
    rows.push_back(summary_row(record, fit));
  }
  const std::vector<AxisAssignment> no_values;
  const std::vector<AxisAssignment>& study_values =
      record.fits.empty() ? no_values : record.fits.front().point.study_values;
  const std::vector<std::string> metric_names = metric_names_of(record);
  const auto columns =
      summary_columns(metric_names, false, study_values, integer_metric_names(record.metric_specs));
  file.create_table(staging + "/fit_metrics", columns);
  file.append_rows(staging + "/fit_metrics", rows);
  write_metric_specs(file, staging + "/" + kMetricSpecsTable,
                     declared_columns(record, metric_names));
  if (!study_values.empty()) {
    std::string axes;
    for (const AxisAssignment& value : study_values) axes += (axes.empty() ? "" : ",") + value.key;
    file.write_string_attribute(staging + "/fit_metrics", kStudyAxesAttribute, axes);
  }
  // dims, units, description (dataset_schema.hpp): the store's and the task's declarations
  describe_datasets(file, staging, record.dataset_specs);
  file.write_int64_attribute(staging, kRunDigestAttribute,
                             static_cast<std::int64_t>(run_digest(file, staging)));
  file.flush();
  return staging;
}

void commit_staged_run(Hdf5File& file, const std::string& location, std::int32_t run) {
  const std::string group = run_group(location, run);
  if (file.exists(group)) abandon(file, group);  // an earlier copy: never read
  file.move(staging_group(location, run), group);
  file.write_int64_attribute(group, "complete", 1);  // last: the mark that the run is whole
  drop_staging(file);  // its now empty groups: no /.staging in a reader's view
  file.flush();
}

void write_run(Hdf5File& file, const JobSpec& job, const RunRecord& record) {
  // Two-step commit (see hdf5_file.hpp, "Crashes"): the run is written and
  // flushed under a staging path, then moved to its place and marked complete. A
  // kill can then damage at most the staging group, which a resume discards.
  stage_run(file, job, record);
  commit_staged_run(file, runs_location(job), record.run);
}

std::vector<unsigned char> run_image(const JobSpec& job, const RunRecord& record) {
  Hdf5File image = Hdf5File::create_in_memory("run_" + std::to_string(record.run));
  image.set_gzip_level(job.output.compression);
  write_run(image, job, record);
  return image.file_image();
}

void write_run_image(Hdf5File& file, const JobSpec& job, std::int32_t run,
                     std::span<const unsigned char> image) {
  const Hdf5File source = Hdf5File::open_image(image, "run_" + std::to_string(run));
  const std::string location = runs_location(job);
  if (!run_is_complete(source, location, run)) {
    throw std::runtime_error("the image sent for run " + std::to_string(run) +
                             " does not hold that run complete");
  }
  const std::string group = run_group(location, run);
  const std::string staging = staging_group(location, run);
  if (!file.in_memory()) {
    require_room(file.path(), 2 * static_cast<std::uint64_t>(image.size()) + kCommitOverhead,
                 "run " + std::to_string(run));
  }
  clear_run_slots(file, group, staging);
  file.copy_from(source, group, staging);  // with its complete mark: staging is never kept
  file.flush();
  file.move(staging, group);
  drop_staging(file);
  file.flush();
}

bool run_is_complete(const Hdf5File& file, const std::string& task, std::int32_t run) {
  const std::string group = run_group(task, run);
  if (!file.exists(group) || !file.has_attribute(group, "complete")) return false;
  try {
    return file.read_int64_attribute(group, "complete") == 1;
  } catch (const std::runtime_error&) {  // not the integer write_run sets: never marked
    return false;
  }
}

void discard_run(Hdf5File& file, const std::string& task, std::int32_t run) {
  abandon(file, run_group(task, run));  // damaged: nothing below it is read or freed
  file.flush();
}

void drop_staging(Hdf5File& file) {
  if (file.exists(kStagingRoot)) drop(file, kStagingRoot);
}

std::vector<std::int32_t> stored_runs(const Hdf5File& file, const std::string& task,
                                      std::int32_t runs) {
  std::vector<std::int32_t> ids;
  const std::string task_group = "/" + task;
  if (!file.exists(task_group)) return ids;
  for (const std::string& name : file.member_names(task_group)) {
    if (name.size() < 5 || name.compare(0, 4, "run_") != 0) continue;
    std::int32_t id = 0;
    const char* end = name.data() + name.size();
    const auto [ptr, error] = std::from_chars(name.data() + 4, end, id);
    if (error != std::errc() || ptr != end || id < 0 || id >= runs) continue;
    if (run_group(task, id) == task_group + "/" + name) ids.push_back(id);
  }
  std::sort(ids.begin(), ids.end());
  return ids;
}

std::vector<std::int32_t> complete_runs(const Hdf5File& file, const std::string& task,
                                        std::int32_t runs) {
  std::vector<std::int32_t> complete = stored_runs(file, task, runs);
  std::erase_if(complete, [&](std::int32_t run) { return !run_is_complete(file, task, run); });
  return complete;
}

std::vector<std::int32_t> prepare_for_resume(Hdf5File& file, const JobSpec& job) {
  // Whatever a killed writer left (its staging group, a run not marked
  // complete) may be damaged: abandoned, never read.
  if (file.exists(kStagingRoot)) abandon(file, kStagingRoot);
  std::vector<std::int32_t> complete;
  const std::string location = runs_location(job);
  for (const std::int32_t run : stored_runs(file, location, job.runs)) {
    if (run_is_complete(file, location, run)) {
      complete.push_back(run);
    } else {
      abandon(file, run_group(location, run));
    }
  }
  file.flush();
  return complete;
}

std::int64_t write_summary(Hdf5File& file, const std::string& task, std::int32_t runs) {
  // Staged like a run: the new table is written whole under /.staging, then the
  // old one is moved aside and the new one into its place. A failure (a full
  // disk) leaves the old summary, or none, never a half-written one where
  // readers look, and a later write_summary starts again from the runs.
  const std::string path = "/" + task + "/summary";
  const std::string staged = kStagingRoot + path;
  const std::string retired = kStagingRoot + path + "_old";
  // The metrics' declarations beside it, staged the same way.
  const std::string specs_path = "/" + task + "/" + kMetricSpecsTable;
  const std::string specs_staged = kStagingRoot + specs_path;
  for (const std::string& leftover : {staged, retired, specs_staged, specs_staged + "_old"}) {
    if (file.exists(leftover)) drop(file, leftover);
  }
  std::vector<TableRow> rows;
  std::vector<TableColumn> columns;
  std::string study_axes;
  // The runs' metric declarations united (each range the smallest that holds
  // every configuration's); none from runs written before them.
  std::optional<std::vector<MetricSpec>> declared;
  // A study's configurations: the column `configuration` after `run`, from
  // each group's attribute (a run's own tables do not hold it: a grown study
  // renumbers its configurations, never its runs' data).
  const std::vector<std::string> locations = runs_locations(file, task);
  const bool configurations = locations.front() != task;
  for (const std::string& location : locations) {
    const std::int32_t configuration =
        configurations ? configuration_of(file, location) : std::int32_t{0};
    for (const std::int32_t run : complete_runs(file, location, runs)) {
      const std::string table = run_group(location, run) + "/fit_metrics";
      unite_run_metric_specs(file, run_group(location, run), declared);
      if (columns.empty()) {
        columns = file.read_table_columns(table);
        if (configurations) {
          columns.insert(columns.begin() + 1, TableColumn{"configuration", ColumnType::kInt32, 0});
        }
        if (file.has_attribute(table, kStudyAxesAttribute)) {
          study_axes = file.read_string_attribute(table, kStudyAxesAttribute);
        }
      }
      for (TableRow& row : file.read_table(table)) {
        // The first run's column types: runs of an older ggk (float64 integer
        // metrics) and of this one (int64) make one summary.
        const std::size_t offset = configurations ? 1 : 0;
        for (std::size_t c = 0; c < row.size() && c + (c == 0 ? 0 : offset) < columns.size(); ++c) {
          row[c] = as_column_type(std::move(row[c]), columns[c + (c == 0 ? 0 : offset)].type);
        }
        if (!configurations) {
          rows.push_back(std::move(row));
          continue;
        }
        TableRow with_configuration;
        with_configuration.reserve(row.size() + 1);
        with_configuration.push_back(std::move(row.front()));
        with_configuration.emplace_back(std::in_place_type<std::int32_t>, configuration);
        std::move(row.begin() + 1, row.end(), std::back_inserter(with_configuration));
        rows.push_back(std::move(with_configuration));
      }
    }
  }
  if (!file.in_memory()) {
    std::uint64_t row_bytes = 0;
    for (const TableColumn& column : columns)
      row_bytes += 8 + std::max<std::size_t>(column.string_size, 64);
    require_room(file.path(), 2 * rows.size() * row_bytes + kCommitOverhead, "the summary");
  }
  if (!columns.empty()) {
    file.create_table(staged, columns);
    file.append_rows(staged, rows);
    if (!study_axes.empty()) file.write_string_attribute(staged, kStudyAxesAttribute, study_axes);
    describe_table(file, staged, "one row per fit of every complete run, in run order");
    file.flush();
  }
  if (declared) {
    write_metric_specs(file, specs_staged, *declared);
    describe_table(file, specs_staged, "the summary's metrics: kind, unit, meaning, range");
    file.flush();
  }
  if (file.exists(path)) file.move(path, retired);
  if (!columns.empty()) file.move(staged, path);
  if (declared) {
    if (file.exists(specs_path)) file.move(specs_path, specs_staged + "_old");
    file.move(specs_staged, specs_path);
  }
  file.flush();
  drop_staging(file);
  file.flush();
  return static_cast<std::int64_t>(rows.size());
}

std::int64_t write_summary(Hdf5File& file, const JobSpec& job) {
  return write_summary(file, job.task, job.runs);
}

void write_configuration_group(Hdf5File& file, const std::string& location, std::int64_t index,
                               const std::string& study_values) {
  const std::string group = "/" + location;
  if (!file.exists(group)) file.create_group(group);
  for (const char* name : {kConfigurationAttribute, kStudyValuesAttribute}) {
    if (file.has_attribute(group, name)) file.remove_attribute(group, name);
  }
  file.write_int64_attribute(group, kConfigurationAttribute, index);
  file.write_string_attribute(group, kStudyValuesAttribute, study_values);
}

bool records_configuration(const Hdf5File& file, const std::string& location, std::int64_t index) {
  const std::string group = "/" + location;
  return file.has_attribute(group, kConfigurationAttribute) &&
         file.read_int64_attribute(group, kConfigurationAttribute) == index;
}

std::optional<std::string> study_values_of(const Hdf5File& file, const std::string& location) {
  const std::string group = "/" + location;
  if (!file.has_attribute(group, kStudyValuesAttribute)) return std::nullopt;
  return file.read_string_attribute(group, kStudyValuesAttribute);
}

std::int32_t configuration_of(const Hdf5File& file, const std::string& location) {
  const std::string group = "/" + location;
  const std::int64_t index = file.has_attribute(group, kConfigurationAttribute)
                                 ? file.read_int64_attribute(group, kConfigurationAttribute)
                                 : -1;
  if (index < 0 || index > INT32_MAX) {
    throw std::runtime_error(group + " has no valid 'configuration' attribute");
  }
  return static_cast<std::int32_t>(index);
}

bool is_configuration_group_name(std::string_view name) {
  if (name.size() < 8 || name.substr(0, 7) != "config_") return false;
  return std::all_of(name.begin() + 7, name.end(), [](char c) { return c >= '0' && c <= '9'; });
}

std::vector<std::string> runs_locations(const Hdf5File& file, const std::string& task) {
  std::vector<std::string> configurations;
  const std::string task_group = "/" + task;
  if (file.exists(task_group)) {
    for (const std::string& name : file.member_names(task_group)) {
      if (is_configuration_group_name(name)) configurations.push_back(task + "/" + name);
    }
  }
  if (configurations.empty()) return {task};
  std::sort(configurations.begin(), configurations.end(),
            [](const std::string& a, const std::string& b) {
              return a.size() != b.size() ? a.size() < b.size() : a < b;  // config_1000 last
            });
  return configurations;
}

}  // namespace ggk::engine
