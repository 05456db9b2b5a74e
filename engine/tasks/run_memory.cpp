#include "engine/tasks/run_memory.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace ggk::engine {

namespace {

// Bytes per entry of the containers the kernels build: an Eigen triplet
// (int32 row, int32 col, double), a compressed sparse entry (int32 index,
// double value), a WeightedEdge (int32, int32, double), a dense double.
constexpr double kTriplet = 16.0;
constexpr double kSparseEntry = 12.0;
constexpr double kEdge = 16.0;
constexpr double kDouble = 8.0;

}  // namespace

double RunMemoryEstimate::run_bytes() const {
  double total = 0.0;
  for (const MemoryItem& item : items) total += item.per_fit ? 0.0 : item.bytes;
  return total;
}

double RunMemoryEstimate::fit_bytes() const {
  double total = 0.0;
  for (const MemoryItem& item : items) total += item.per_fit ? item.bytes : 0.0;
  return total;
}

std::string count_text(double count) {
  char text[48];
  std::snprintf(text, sizeof text, count < 1e15 ? "%.0f" : "%.3g", count);
  return text;
}

std::string format_bytes(double bytes) {
  static constexpr std::array<const char*, 5> kUnits = {"B", "kB", "MB", "GB", "TB"};
  std::size_t unit = 0;
  while (bytes >= 999.5 && unit + 1 < kUnits.size()) {
    bytes /= 1000.0;
    ++unit;
  }
  char text[48];
  if (unit == 0) {
    std::snprintf(text, sizeof text, "%.0f B", bytes);
  } else if (bytes >= 1000.0) {  // beyond the largest unit
    std::snprintf(text, sizeof text, "%.2g %s", bytes, kUnits[unit]);
  } else {
    std::snprintf(text, sizeof text,
                  bytes >= 99.95 ? "%.0f %s" : (bytes >= 9.995 ? "%.1f %s" : "%.2f %s"), bytes,
                  kUnits[unit]);
  }
  return text;
}

double kernel_and_feature_bytes(double states, double kernels, double actions) {
  const double entries = states * kernels;
  // While the kernel table is built: the triplet list, reserved for every entry,
  // the row-major matrix and the transposed copy setFromTriplets() sorts through.
  const double building = entries * (kTriplet + 2.0 * kSparseEntry);
  // Then the kernel table and the feature table (copy or shift: m rows per state,
  // each with the state's kernel entries in its action's block).
  const double tables = entries * kSparseEntry * (1.0 + actions);
  return std::max(building, tables) + states * actions * kDouble;  // + row pointers
}

double kernel_table_bytes(double states, double kernels) {
  return states * kernels * kSparseEntry + (states + 1.0) * 4.0;
}

double lspi_bytes(double states, double kernels, double actions, double samples) {
  const double k = actions * kernels;  // basis functions
  // ActionBlockSystem: D_a (m blocks of p x p), the dense A (k x k), E_b (BRM),
  // and the gathered sample blocks of one action pair (n / m rows of p, twice).
  const double dense = kDouble * (k * k + 2.0 * actions * kernels * kernels) +
                       2.0 * kDouble * samples / actions * kernels;
  // A compressed for the solver, the last iteration's A kept in the result, and
  // the factorisation: CHOLMOD's L or UMFPACK's LU, dense in the worst case. The
  // dense kind ([lspi] linear_algebra) holds less: the last A and LAPACK's factor
  // dense (2 k^2 doubles) and A compressed once, at the end.
  const double sparse = 2.0 * kSparseEntry * k * k + 2.0 * kDouble * k * k;
  // Per state: Q (m values), the current and improved policies, on_samples; per
  // sample: the square-root weights and the grouping indices.
  const double vectors = states * (actions * kDouble + 9.0) + samples * 16.0;
  return dense + sparse + vectors;
}

double fit_record_bytes(double states, double kernels, double actions, bool lower_triangle) {
  const double k = actions * kernels;
  const double system = kSparseEntry * k * k * (lower_triangle ? 0.5 : 1.0) + 2.0 * kDouble * k;
  return system + states * (4.0 + 2.0 * kDouble);  // policy, state values, steps
}

double sample_batch_bytes(double samples) {
  // states, actions, next_states (int32), rewards, weights (double), terminals.
  return 2.0 * samples * (3.0 * 4.0 + 2.0 * kDouble + 1.0);
}

double graph_building_bytes(double transitions) {
  return transitions * 3.0 * kEdge;
}

double graph_bytes(double transitions, double nodes) {
  const double arcs = std::min(2.0 * transitions, nodes * nodes);
  return arcs * kSparseEntry + nodes * kDouble;
}

double folding_bytes(double samples, double distinct) {
  // std::unordered_map<Key, size_t>: 8-byte buckets, reserved for every sample;
  // a node (key, value, hash, link) of about 64 bytes with malloc's overhead.
  return samples * kDouble + distinct * 64.0;
}

}  // namespace ggk::engine
