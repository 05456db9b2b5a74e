#include "engine/run/memory_check.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include <tbb/global_control.h>

#include "engine/job/sweep.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/address_space.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {

namespace fs = std::filesystem;

namespace {

// Libraries, oneTBB, thread stacks (22 MB measured for a tiny job) and HDF5's
// metadata cache, which grows with the objects written (to ~42 MB after a few
// runs of jobs/ci.toml, then flat).
constexpr double kProgramBytes = 48e6;
constexpr double kRunListBytes = 12.0;  // per run: pending, complete, the MPI queue (int32 each)
constexpr double kSummaryRowBytes = 1000.0;  // per fit: ~15 std::variant cells, the packed row
// A cgroup "limit" this large means none (v1 writes 2^63 rounded to pages).
constexpr double kNoLimit = 1e18;

// The first number in a file ("max" and unreadable files: nothing).
std::optional<double> read_number(const fs::path& path) {
  std::ifstream in(path);
  double value = 0.0;
  if (in >> value) return value;
  return std::nullopt;
}

// The value of `key` in a "key value" file (memory.stat, /proc/meminfo).
std::optional<double> read_keyed(const fs::path& path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string name;
    double value = 0.0;
    if (fields >> name >> value && (name == key || name == key + ":")) return value;
  }
  return std::nullopt;
}

// The cgroup paths of this process from /proc/self/cgroup: v2's ("0::/path")
// and v1's memory controller ("N:memory:/path").
struct CgroupPaths {
  std::optional<std::string> v2, v1_memory;
};

CgroupPaths cgroup_paths() {
  CgroupPaths paths;
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1);
    const std::string path = line.substr(second + 1);
    if (line.compare(0, first, "0") == 0 && controllers.empty()) paths.v2 = path;
    std::istringstream list(controllers);
    for (std::string c; std::getline(list, c, ',');) {
      if (c == "memory") paths.v1_memory = path;
    }
  }
  return paths;
}

// The folders from `mount` + `path` up to `mount` (the group and its ancestors;
// in a container the group's own path may not exist under the mount, then the
// mount's root is the group).
std::vector<fs::path> group_and_ancestors(const fs::path& mount, const std::string& path) {
  std::vector<fs::path> folders;
  std::error_code ec;
  fs::path folder = mount / fs::path(path).relative_path();
  if (!fs::is_directory(folder, ec)) folder = mount;
  for (;;) {
    folders.push_back(folder);
    if (folder == mount || !folder.has_relative_path() || folder.parent_path() == folder) break;
    folder = folder.parent_path();
  }
  return folders;
}

void take_least(AvailableMemory& available, double bytes, std::string source) {
  if (bytes < available.bytes) available = {std::max(bytes, 0.0), std::move(source)};
}

// One cgroup level: what its limit leaves, page cache counted as free.
void take_cgroup(AvailableMemory& available, const fs::path& folder, const char* limit_file,
                 const char* usage_file, const char* inactive_key) {
  const std::optional<double> limit = read_number(folder / limit_file);
  if (!limit || *limit >= kNoLimit) return;
  const double usage = read_number(folder / usage_file).value_or(0.0);
  const double cache = read_keyed(folder / "memory.stat", inactive_key).value_or(0.0);
  take_least(available, *limit - std::max(usage - cache, 0.0),
             "the cgroup memory limit " + (folder / limit_file).string() + ", less its usage");
}

}  // namespace

AvailableMemory available_memory(double reserved_address_space) {
  AvailableMemory available;
  if (const auto kib = read_keyed("/proc/meminfo", "MemAvailable")) {
    take_least(available, *kib * 1024.0, "MemAvailable in /proc/meminfo");
  }
  const CgroupPaths groups = cgroup_paths();
  if (groups.v2) {
    for (const fs::path& folder : group_and_ancestors("/sys/fs/cgroup", *groups.v2)) {
      take_cgroup(available, folder, "memory.max", "memory.current", "inactive_file");
    }
  }
  if (groups.v1_memory) {
    for (const fs::path& folder : group_and_ancestors("/sys/fs/cgroup/memory", *groups.v1_memory)) {
      take_cgroup(available, folder, "memory.limit_in_bytes", "memory.usage_in_bytes",
                  "total_inactive_file");
    }
  }
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    const double in_use = address_space_in_use();
    take_least(available, static_cast<double>(limit.rlim_cur) - in_use - reserved_address_space,
               "the address-space limit (ulimit -v) of " +
                   format_bytes(static_cast<double>(limit.rlim_cur)) + ", less " +
                   format_bytes(in_use) + " in use" +
                   (reserved_address_space > 0.0
                        ? " and " + format_bytes(reserved_address_space) +
                              " the threads reserve (BLAS buffers, malloc arenas, stacks)"
                        : std::string()));
  }
  return available;
}

JobMemoryEstimate estimate_job_memory(const JobSpec& job, std::int32_t threads, std::int64_t runs,
                                      std::int64_t variants) {
  const TaskDefinition* task = find_task(job.task);
  if (task == nullptr) throw std::logic_error("job names task '" + job.task + "', not registered");
  const double points = static_cast<double>(expand_sweep(job).size()) *
                        static_cast<double>(std::max<std::int64_t>(variants, 1));
  const double total_runs = static_cast<double>(std::max<std::int64_t>(runs, 0));
  const double workers = std::max(threads, 1);
  const double at_once = std::min(workers, total_runs);
  const double fits_at_once = std::min(workers, at_once * points);
  // " x 2 runs at once (2 threads)", or nothing for one at a time.
  auto times = [&](double count, const char* what) {
    return count > 1.0 ? " x " + count_text(count) + " " + what + " at once (" +
                             count_text(workers) + " threads)"
                       : std::string();
  };

  std::vector<std::pair<double, std::string>> parts;
  parts.emplace_back(kProgramBytes, "the program itself (libraries, HDF5's caches): " +
                                        format_bytes(kProgramBytes));
  JobMemoryEstimate result;
  if (task->estimate_run_bytes != nullptr && at_once > 0.0) {
    const RunMemoryEstimate run = task->estimate_run_bytes(job);
    result.per_run = run.peak(1.0);
    for (const MemoryItem& item : run.items) {
      const double count = item.per_fit ? fits_at_once : at_once;
      parts.emplace_back(count * item.bytes, item.what + ": " + format_bytes(item.bytes) +
                                                 (item.per_fit ? " per fit" : " per run") +
                                                 times(count, item.per_fit ? "fits" : "runs"));
    }
    const double waiting = std::min(at_once, total_runs - at_once);
    if (waiting > 0.0) {
      parts.emplace_back(waiting * run.record_bytes,
                         "finished runs waiting for the writer: " + format_bytes(run.record_bytes) +
                             " per run x " + count_text(waiting));
    }
  }
  parts.emplace_back(total_runs * kRunListBytes, "the lists of runs: " + count_text(total_runs) +
                                                     " runs x " + format_bytes(kRunListBytes));
  parts.emplace_back(total_runs * points * kSummaryRowBytes,
                     "the summary table, held in memory at the end: " + count_text(total_runs) +
                         " runs x " + count_text(points) + " sweep points x ~1 kB");

  // The total, and the largest parts that make up most of it (at most three).
  for (const auto& part : parts) result.bytes += part.first;
  std::stable_sort(parts.begin(), parts.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  double covered = 0.0;
  for (std::size_t i = 0; i < parts.size() && i < 3; ++i) {
    if (i > 0 && (covered >= 0.8 * result.bytes || parts[i].first < 0.1 * result.bytes)) break;
    result.largest += (i > 0 ? "; " : "") + parts[i].second;
    covered += parts[i].first;
  }
  return result;
}

void check_memory(const JobSpec& job, std::int32_t threads, std::int64_t runs, bool ignore,
                  std::int64_t variants) {
  const JobMemoryEstimate estimate = estimate_job_memory(job, threads, runs, variants);
  // oneTBB starts every thread it may use, each reserving address space.
  const AvailableMemory available = available_memory(reserved_address_space(threads));
  if (!(estimate.bytes > available.bytes)) return;
  const std::string what = "job '" + job.name + "' needs about " + format_bytes(estimate.bytes) +
                           " of memory, more than the " + format_bytes(available.bytes) +
                           " available (" + available.source + "); most of it: " + estimate.largest;
  const bool address_space = available.source.find("ulimit -v") != std::string::npos;
  if (ignore) {
    // OpenBLAS retries a failed work-buffer allocation forever (address_space.hpp).
    std::fprintf(
        stderr, "ggk: note: %s; running it anyway (--ignore-memory-check)%s\n", what.c_str(),
        address_space ? ": out of address space, a BLAS call may hang instead of failing" : "");
    return;
  }
  throw UsageError(what + ". Make the job smaller, run fewer threads with -j" +
                   (address_space ? ", raise the address-space limit (ulimit -v)" : "") +
                   " or pass --ignore-memory-check to run it anyway");
}

void check_memory(const JobSpec& job, const RunOptions& options, std::int64_t variants) {
  const std::size_t allowed =
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  const auto threads = static_cast<std::int32_t>(std::min<std::size_t>(allowed, 1 << 20));
  std::int64_t runs = job.runs;
  if (options.runs) {  // a bad range is open_results' to report
    runs = std::max<std::int64_t>(
        std::min<std::int64_t>(options.runs->last, job.runs) - std::max(options.runs->first, 0), 0);
  }
  check_memory(job, threads, runs, options.ignore_memory_check, variants);
}

}  // namespace ggk::engine
