#pragma once
// The bytes a RunRecord holds (vector and matrix payloads, no allocator
// overhead): the lower bound a task's RunMemoryEstimate::record_bytes must meet.

#include <cstddef>

#include "engine/tasks/run_record.hpp"

namespace ggk::engine {

inline double record_bytes(const RunRecord& record) {
  auto bytes = [](const auto& container) {
    return static_cast<double>(container.size()) * sizeof(*container.data());
  };
  const SampleRecord& s = record.samples;
  double total = bytes(s.observations) + bytes(s.next_observations) + bytes(s.actions) +
                 bytes(s.rewards) + bytes(s.terminals);
  total += bytes(record.graph.indptr) + bytes(record.graph.indices) + bytes(record.graph.weights) +
           bytes(record.node_states);
  for (const NamedArray& array : record.arrays) total += bytes(array.values);
  for (const FitRecord& fit : record.fits) {
    total += bytes(fit.centers) + bytes(fit.lspi.weights) + bytes(fit.lspi.policy) +
             bytes(fit.lspi.b) + static_cast<double>(fit.lspi.a.nonZeros()) * 12.0;
    for (const NamedArray& array : fit.arrays) total += bytes(array.values);
  }
  return total;
}

}  // namespace ggk::engine
