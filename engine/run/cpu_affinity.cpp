#include "engine/run/cpu_affinity.hpp"

#include <sched.h>

#include <cerrno>
#include <cstddef>
#include <memory>

namespace ggk::engine {

std::vector<std::int32_t> affinity_cpus() {
  // CPU_ALLOC sets: machines may have more CPUs than a cpu_set_t holds (1024);
  // EINVAL means the kernel's mask is larger than the set asked with.
  for (int size = 1024; size <= (1 << 20); size *= 2) {
    const auto free_set = [](cpu_set_t* set) { CPU_FREE(set); };  // CPU_FREE is a macro
    const std::unique_ptr<cpu_set_t, decltype(free_set)> set(CPU_ALLOC(size), free_set);
    if (!set) return {};
    const std::size_t bytes = CPU_ALLOC_SIZE(size);
    CPU_ZERO_S(bytes, set.get());
    if (sched_getaffinity(0, bytes, set.get()) != 0) {
      if (errno == EINVAL) continue;
      return {};
    }
    std::vector<std::int32_t> cpus;
    for (int cpu = 0; cpu < size; ++cpu) {
      if (CPU_ISSET_S(cpu, bytes, set.get())) cpus.push_back(cpu);
    }
    return cpus;
  }
  return {};
}

std::string describe_cpus(std::span<const std::int32_t> cpus) {
  std::string text;
  for (std::size_t i = 0; i < cpus.size();) {
    std::size_t j = i;
    while (j + 1 < cpus.size() && cpus[j + 1] == cpus[j] + 1) ++j;
    if (!text.empty()) text += ',';
    text += std::to_string(cpus[i]);
    if (j > i) text += '-' + std::to_string(cpus[j]);
    i = j + 1;
  }
  return text;
}

std::optional<std::string> oversubscription_warning(std::int32_t threads,
                                                    std::span<const std::int32_t> cpus) {
  const auto available = static_cast<std::int32_t>(cpus.size());
  if (threads <= 0 || cpus.empty() || threads <= available) return std::nullopt;
  return "-j " + std::to_string(threads) + " starts " + std::to_string(threads) +
         " compute threads, but this process may run on " + std::to_string(available) +
         (available == 1 ? " CPU" : " CPUs") + " (its affinity mask: " + describe_cpus(cpus) +
         "), so they will share " + (available == 1 ? "it" : "them") +
         ". Under srun, give the step its CPUs: srun --cpus-per-task=N (since Slurm 22.05 "
         "a step does not inherit the allocation's --cpus-per-task; or export "
         "SRUN_CPUS_PER_TASK=$SLURM_CPUS_PER_TASK); under mpirun, --map-by slot:PE=N or "
         "--bind-to none; or leave -j out (all CPUs of the mask)";
}

}  // namespace ggk::engine
