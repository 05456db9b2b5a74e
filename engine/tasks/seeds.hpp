#pragma once
// Random streams of a job: keyed by (root seed, run, purpose[, item]) so that a
// result never depends on thread count, scheduling order or MPI rank count.

#include <cstdint>

#include "kernels/random_stream.hpp"

namespace ggk::engine {

// What a stream's numbers are for. Values are part of the file format's
// reproducibility: never renumber, only append.
enum class Purpose : std::uint32_t {
  samples = 1,     // the run's random-walk samples
  centers = 2,     // the order in which graph nodes become kernel centres
  evaluation = 3,  // testing a fit's greedy policy: one stream per run, read afresh by
                   // every fit (common random numbers: two fits of a run meet the
                   // same test noise, so they compare paired by run; a fit's
                   // results do not depend on which other fits its job has)
  model = 4,       // task-specific model fitting (e.g. the SOM)
};

// item distinguishes streams of the same purpose within a run (e.g. sweep points);
// it must be < 2^24.
inline kernels::RandomStream stream_for(std::uint64_t seed, std::int32_t run, Purpose purpose,
                                        std::uint32_t item = 0) {
  return kernels::RandomStream(seed, static_cast<std::uint32_t>(run),
                               (static_cast<std::uint32_t>(purpose) << 24) | (item & 0xFFFFFFu));
}

}  // namespace ggk::engine
