#pragma once
// The CPUs a process may run on, and the warning `ggk run` prints at start when
// -j asks for more threads than that: a launcher that binds each rank to fewer
// CPUs (srun without --cpus-per-task since Slurm 22.05, mpirun's bind-to-core,
// taskset, a container's cpuset) makes the threads share them, silently.
// Thread-safe: no state.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ggk::engine {

// sched_getaffinity of this process: the CPU numbers, ascending; empty when the
// mask cannot be read.
std::vector<std::int32_t> affinity_cpus();

// {0, 1, 2, 3, 8, 10, 11} -> "0-3,8,10-11" (ascending input).
std::string describe_cpus(std::span<const std::int32_t> cpus);

// The warning for `threads` threads (-j; 0 = oneTBB's default, which follows the
// mask) on `cpus`; nullopt when they fit or the mask is unknown (empty).
std::optional<std::string> oversubscription_warning(std::int32_t threads,
                                                    std::span<const std::int32_t> cpus);

}  // namespace ggk::engine
