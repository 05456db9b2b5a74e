#pragma once
// What one run of a job holds in memory at its peak, item by item, estimated
// from the job alone (nothing is allocated): the runner's memory check
// (engine/run/memory_check.hpp) refuses a job that cannot fit before it creates
// the output file, and names the item that dominates.
//
// Bytes are doubles: a job's sizes multiply to far beyond 2^64 (2^31 samples x
// 2^31 steps), and a double saturates gracefully where an integer would wrap.
// An estimate aims at the peak resident memory within a factor of about 2; the
// formulas follow what the code allocates (triplet lists, sparse tables, dense
// LSPI systems, vectors grown by doubling) and are written out where they are
// used (discrete_protocol.cpp, khepera_task.cpp). Measured against peak RSS in
// engine/tasks/README.md.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace ggk::engine {

// One part of a run's memory, e.g. {"200000 samples (series x steps_per_series)", 3.2e7}.
struct MemoryItem {
  std::string what;
  double bytes = 0.0;
  // Held by every fit in flight (a run's fits run in parallel) rather than once
  // per run: kernel and feature tables, the LSPI system and its factorisation.
  bool per_fit = false;
};

struct RunMemoryEstimate {
  std::vector<MemoryItem> items;
  // The finished run record (its share of the items), held until the store's
  // writer has written it.
  double record_bytes = 0.0;

  void add(std::string what, double bytes) { items.push_back({std::move(what), bytes, false}); }
  void add_per_fit(std::string what, double bytes) {
    items.push_back({std::move(what), bytes, true});
  }

  double run_bytes() const;  // the items held once per run
  double fit_bytes() const;  // the items held per fit in flight
  // One run's peak with `fits_in_flight` of its fits computing at once.
  double peak(double fits_in_flight) const { return run_bytes() + fits_in_flight * fit_bytes(); }
};

// A count as the messages show it: "2147483647".
std::string count_text(double count);

// "512 B", "40.0 MB", "12.8 GB", "3.4e+06 TB": decimal units, 3 significant digits.
std::string format_bytes(double bytes);

// Building blocks shared by the tasks' estimates. `states` is the number of rows
// of the kernel table (every state of a discrete task, every reading of a Khepera
// run), `kernels` a fit's kernel count p, `actions` m, `samples` the LSPI batch.

// A fit's state-kernel table (triplet list, sparse matrix and its transposed
// copy while it is built) and its state-action feature table (m rows per state),
// at full density: a Gaussian kernel is zero only where it underflows.
double kernel_and_feature_bytes(double states, double kernels, double actions);

// A state-kernel table built in place (kernels/gaussian_kernels.cpp): compressed
// arrays sized for every entry (kept at that size when entries are dropped) and
// the row pointers. Also a table of a table's first columns (khepera_task.cpp).
double kernel_table_bytes(double states, double kernels);

// A fit's LSPI: the dense k x k system (k = m p), its compressed copies (the
// current and the last iteration's), the sparse factorisation (dense in the worst
// case), the per-action sample blocks, and the policy and Q vectors over the
// states.
double lspi_bytes(double states, double kernels, double actions, double samples);

// What a fit keeps in the run record: the last LSPI system (A, b, weights; BRM
// stores A's lower triangle only), the greedy policy and the state values.
double fit_record_bytes(double states, double kernels, double actions, bool lower_triangle);

// A SampleBatch of n samples (6 vectors, grown by doubling: up to 2x).
double sample_batch_bytes(double samples);

// transition_graph() on n transitions: the edge list and the arc list (both
// directions), alive together while the arcs are sorted and freed on return.
double graph_building_bytes(double transitions);

// The CSR sample graph it returns over `nodes` nodes (at most min(2n, nodes^2) arcs).
double graph_bytes(double transitions, double nodes);

// fold_duplicate_samples() on n samples of which `distinct` differ: its hash map
// (a bucket per sample, a node per distinct sample) while it runs.
double folding_bytes(double samples, double distinct);

}  // namespace ggk::engine
