#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "engine/job/sweep.hpp"
#include "engine/tasks/continuous_protocol.hpp"
#include "engine/tasks/pvf_basis.hpp"

namespace ggk::engine {

RunMemoryEstimate estimate_continuous_run(const ContinuousSizes& sizes,
                                          const ContinuousProtocol& protocol, const JobSpec& job) {
  const double d = sizes.observation_dimension, m = sizes.actions;
  const double steps = sizes.series_steps > 0.0
                           ? std::min<double>(sizes.series_steps, protocol.steps_per_series)
                           : protocol.steps_per_series;
  const double n = static_cast<double>(protocol.series) * steps;  // samples
  const double readings = static_cast<double>(protocol.series) * (steps + 1.0);
  kernels::SomGrid grid{protocol.som.rows, protocol.som.cols};
  if (protocol.som_grid_from_samples)
    grid = kernels::som_grid_for(static_cast<std::int64_t>(readings));
  const double units = static_cast<double>(grid.rows) * grid.cols;
  const std::vector<SweepPoint> points = expand_sweep(job);
  double max_kernels = 0.0;
  for (const SweepPoint& p : points) max_kernels = std::max<double>(max_kernels, p.kernels);
  max_kernels = std::min(max_kernels, units);  // a fit with more kernels than units never starts
  const bool shift = job.basis.scheme == kernels::BasisScheme::shift;

  RunMemoryEstimate estimate;
  // Observations (d doubles each, and their scaled copy) with their
  // best-matching units (and as doubles in the record); samples: the walks'
  // batch and stop flags (grown by doubling), their copy in the record, the LSPI
  // batch (every observation is its own state: folding keeps every sample) and
  // the graph's transition list; then first the folding's hash map or the
  // graph's edge lists; the shift scheme's transition model over the observations.
  const double record_samples = n * (2.0 * d * 8.0 + 13.0 + 8.0 * sizes.stop_flags);
  estimate.add(
      count_text(n) + " samples per run (series x steps_per_series)",
      readings * (2.0 * d * 8.0 + 12.0 + 8.0) + sample_batch_bytes(n) +
          16.0 * sizes.stop_flags * n + record_samples + sample_batch_bytes(n) + 8.0 * n +
          std::max(job.lspi.fold_duplicates ? folding_bytes(n, n) : 0.0, graph_building_bytes(n)) +
          (shift ? readings * m * 8.0 + 20.0 * n : 0.0));
  // The SOM: training (prototypes, their dimension-major copy, the per-unit sums
  // and two smoothing passes over them: about 5 d + 3 doubles a unit) bounds
  // what the map keeps afterwards (prototypes twice, in the record, as graph
  // nodes, grid). Plus the unit graph.
  estimate.add("a " + count_text(grid.rows) + " x " + count_text(grid.cols) + " SOM (" +
                   count_text(units) + " units)",
               units * (5.0 * d + 3.0) * 8.0 + graph_bytes(n, units));
  estimate.add("the geodesic distances from " + count_text(max_kernels) + " centres to " +
                   count_text(units) + " units",
               max_kernels * units * 8.0);
  // The proto-value functions (pvf_basis.hpp): per "pvf" kernel count P its
  // eigenvectors over the units (and the eigensolve's copy of them), the Lanczos
  // basis while it runs (at most 2 P + 20 vectors), the Laplacian (an entry per
  // arc and unit) and CHOLMOD's factor (taken as ten times the Laplacian's
  // entries). A fit reads its count's vectors through one row per unit.
  double pvf_vectors = 0.0, largest_count = 0.0;
  for (const std::int32_t count :
       pvf_counts(points, static_cast<std::int32_t>(std::min<double>(units, 2147483647.0)))) {
    pvf_vectors += count;
    largest_count = std::max<double>(largest_count, count);
  }
  if (pvf_vectors > 0.0) {
    estimate.add("the proto-value functions (" + count_text(pvf_vectors) + " eigenvectors of " +
                     count_text(units) + " units)",
                 units * (2.0 * pvf_vectors + 2.0 * largest_count + 20.0) * 8.0 +
                     11.0 * (2.0 * n + units) * 12.0);
  }
  // The kernel gap's two distance rows (a double per observation each) per
  // centre in flight while its per-centre sums are formed (two: one per thread
  // of -j 2).
  estimate.add("the kernel gap's distance rows (" + count_text(readings) + " observations)",
               2.0 * readings * 16.0);
  // The GGK and OGK tables of the largest kernel count, one per basis and width,
  // held while the run's fits take their counts' tables (the leading columns of
  // it, continuous_protocol.cpp: kernel_bases).
  std::vector<std::pair<KernelType, double>> bases;
  double base_kernels = 0.0;
  for (const SweepPoint& p : points) {
    if (p.basis == KernelType::pvf) continue;
    const std::pair<KernelType, double> base{p.basis, p.sigma};
    if (std::find(bases.begin(), bases.end(), base) == bases.end()) bases.push_back(base);
    base_kernels = std::max<double>(base_kernels, std::min<double>(p.kernels, units));
  }
  if (!bases.empty()) {
    estimate.add("the largest kernel count's table of " +
                     count_text(static_cast<double>(bases.size())) + " basis and width pairs (" +
                     count_text(base_kernels) + " kernels)",
                 static_cast<double>(bases.size()) * kernel_table_bytes(readings, base_kernels));
  }
  // A fit's state kernels, shared with the fits of the other solvers at the
  // same basis, width and kernel count; the shift scheme forms its m-row
  // feature table from them.
  estimate.add_per_fit(shift ? "the kernel and feature tables of a fit with " +
                                   count_text(max_kernels) + " kernels (" + count_text(readings) +
                                   " observations x " + count_text(m) + " actions)"
                             : "the state kernels of a fit with " + count_text(max_kernels) +
                                   " kernels (" + count_text(readings) +
                                   " observations; the copy scheme forms no feature table)",
                       shift ? kernel_and_feature_bytes(readings, max_kernels, m)
                             : kernel_table_bytes(readings, max_kernels));
  estimate.add_per_fit("the LSPI system of a fit with " + count_text(m) + " x " +
                           count_text(max_kernels) + " basis functions",
                       lspi_bytes(readings, max_kernels, m, n));
  // The fits' results: LSPI systems, policies, the greedy action per unit, and
  // the episodes' trajectories (up to test_max_steps + 1 points of
  // trace_dimension doubles, grown by doubling).
  const double episodes = static_cast<double>(protocol.test_episodes) *
                          (protocol.test_max_steps + 1.0) * sizes.trace_dimension * 16.0;
  double fits = 0.0;
  for (const SweepPoint& p : points) {
    fits += fit_record_bytes(readings, std::min<double>(p.kernels, units), m,
                             p.solver == kernels::LspiSolver::brm) +
            episodes + units * 8.0;
  }
  estimate.add("the results of " + count_text(static_cast<double>(points.size())) + " fits", fits);
  estimate.record_bytes = record_samples + readings * 8.0 + units * (16.0 * d + 24.0) +
                          graph_bytes(n, units) + fits + sizes.simulator_bytes;
  return estimate;
}

}  // namespace ggk::engine
