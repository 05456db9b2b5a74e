#pragma once
// What a results file holds, as plain data: its header and every fit of its
// complete runs (their fit_metrics rows), configuration by configuration in run
// order; what a running or killed job has done so far. `ggk info` summarises it
// (results_info.hpp), an adaptive study decides its cells from it
// (adaptive_state.hpp).
//
// HDF5 calls: one thread at a time (the StoreWriter's while a job writes).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/store/results_layout.hpp"
#include "engine/store/run_store.hpp"
#include "engine/tasks/metric_spec.hpp"

namespace ggk::engine {

// What `ggk info` reads from a results file, as plain data: the header, how many
// runs are complete, and every fit of the complete runs (fit_metrics rows).
struct FitRow {
  std::int64_t run = 0;
  std::int64_t point = 0;           // (configuration << 32) + its sweep point's index
  std::int32_t configuration = 0;   // its run configuration's index (0: a plain job)
  std::vector<std::string> key;     // its axis values as text
  std::optional<FitStatus> status;  // none for a status this ggk does not know
  std::vector<double> values;       // per metric column
};

struct ResultsContents {
  ResultsHeader header;
  std::size_t complete_runs = 0;
  std::size_t configurations = 1;         // a study's run configurations (run_store.hpp)
  bool summary_written = false;           // /<task>/summary exists
  std::vector<std::string> axis_names;    // the sweep point's axes (basis, kernels, ...)
  std::vector<std::string> metric_names;  // the metrics the task reports, then fit_seconds
  // Their declarations, one per name (metric_specs_table.hpp): the complete
  // runs' united; for a metric no run declares (a file written before the
  // declarations), legacy_metric_spec's.
  std::vector<MetricSpec> metric_specs;
  bool metrics_declared = false;  // some complete run declares its metrics
  std::vector<FitRow> fits;       // in run order
};

// The rows of every complete run. Their columns: run, sweep_point, the point's
// axes up to status (the built-in ones, then a study's keys), then the metrics and
// fit_seconds. Throws UsageError when the file is no results file.
ResultsContents read_contents(const Hdf5File& file);

// A table cell as a number (NaN for text) and as text (numbers in their
// shortest exact form: 1e-06).
double as_double(const TableValue& v);
std::string as_text(const TableValue& v);

}  // namespace ggk::engine
