#pragma once
// Kernel widths that cannot work: refused when the job is read, not discovered
// as fits that "converge" in one iteration.
//
// A Gaussian kernel is exp(-d^2 / (2 sigma^2)) (kernels::gaussian). At a width
// far below the task's distances every kernel value between distinct states
// underflows to 0, and the basis is the centres' indicator functions; far above
// them every value rounds to 1, and the basis is constant. Each task knows the
// distances its kernels meet (its DistanceScale) and calls check_kernel_widths()
// from its table parser; the bounds are the exact arithmetic of
// kernels::gaussian, not rules of thumb.

#include <string>

#include "engine/job/toml_table_reader.hpp"

namespace ggk::engine {

// The distances a task's kernels meet, in the units of its state vectors.
struct DistanceScale {
  double smallest = 1.0;    // > 0: no two distinct states are closer
  double largest = 1.0;     // >= every distance a kernel is given (geodesic ones included)
  std::string smallest_is;  // what `smallest` is, for messages: "between neighbouring cells"
  std::string largest_is;   // what `largest` bounds: "states x the grid's diagonal"
};

// Throws JobError at the first value of [sweep] sigma for which
// gaussian(scale.smallest, sigma) == 0 (every value between distinct states is 0)
// or gaussian(scale.largest, sigma) == 1 (every value is 1). `job` is the job
// file's root table, whose [sweep] table parse_job() has read (and checked)
// before it calls the task's parser.
void check_kernel_widths(const TomlTableReader& job, const DistanceScale& scale);

}  // namespace ggk::engine
