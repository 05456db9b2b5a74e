// estimate_khepera_run: grows with the walks, the SOM and the kernels; a
// 40000 x 40000 SOM (issue 13, item 10) is estimated at far over 10 GB, finite;
// and the estimate is no less than what a run's record holds.

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/khepera/khepera_task.hpp"
#include "engine/tasks/record_bytes.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

struct KheperaJob {
  long long series = 10;
  long long steps = 50;
  std::string kernels = "[5, 10]";
  std::string som = "rows = 4\ncols = 5";
  long long test_max_steps = 30;
  std::string scheme;  // [basis] scheme; the default when empty
  std::string basis = "[\"ggk\", \"ogk\"]";
};

JobSpec parse(const KheperaJob& k) {
  const std::string text =
      "name = \"k\"\ntask = \"khepera\"\nruns = 1\nseed = 7\n[sweep]\n"
      "basis = " +
      k.basis + "\nkernels = " + k.kernels +
      "\nsigma = [1000.0]\n[khepera]\nseries = " + std::to_string(k.series) +
      "\nsteps_per_series = " + std::to_string(k.steps) +
      "\ntest_max_steps = " + std::to_string(k.test_max_steps) +
      "\ntest_episodes = 2\n[khepera.som]\n" + k.som +
      "\n[khepera.arena]\nmin = [0.0, 0.0]\nmax = [40.0, 40.0]\n"
      "start = { x = 20.0, y = 20.0, heading_deg = 0.0 }\n" +
      (k.scheme.empty() ? "" : "[basis]\nscheme = \"" + k.scheme + "\"\n");
  JobLoadOptions options;
  options.check_output = false;
  return parse_job(text, "memory.toml", task_tables(), options);
}

RunMemoryEstimate estimate(const KheperaJob& k) {
  return find_task("khepera")->estimate_run_bytes(parse(k));
}

const MemoryItem& item_naming(const RunMemoryEstimate& e, const std::string& part) {
  for (const MemoryItem& item : e.items) {
    if (item.what.find(part) != std::string::npos) return item;
  }
  ADD_FAILURE() << "no item names " << part;
  return e.items.front();
}

TEST(KheperaMemory, GrowsWithWalksSomAndKernels) {
  const KheperaJob base;
  const double peak = estimate(base).peak(1);
  EXPECT_GT(peak, 0.0);
  KheperaJob k = base;
  k.steps = 500;
  EXPECT_GT(estimate(k).peak(1), peak);
  k = base;
  k.series = 100;
  EXPECT_GT(estimate(k).peak(1), peak);
  k = base;
  k.som = "rows = 10\ncols = 20";
  EXPECT_GT(estimate(k).peak(1), peak);
  EXPECT_GT(item_naming(estimate(k), "SOM").bytes, item_naming(estimate(base), "SOM").bytes);
  k = base;
  k.kernels = "[5, 20]";
  EXPECT_GT(estimate(k).fit_bytes(), estimate(base).fit_bytes());
  // The proto-value functions: their eigenvectors per kernel count, over the units.
  const RunMemoryEstimate without_pvf = estimate(base);
  EXPECT_EQ(std::count_if(without_pvf.items.begin(), without_pvf.items.end(),
                          [](const MemoryItem& item) {
                            return item.what.find("proto-value") != std::string::npos;
                          }),
            0);
  k = base;
  k.basis = "[\"ggk\", \"pvf\"]";
  const double with_pvf = item_naming(estimate(k), "proto-value functions (15 eigenvectors").bytes;
  EXPECT_GT(with_pvf, 20.0 * 15 * 8);
  EXPECT_GT(estimate(k).peak(1), peak);
  k.kernels = "[5, 10, 20]";
  EXPECT_GT(item_naming(estimate(k), "proto-value functions (35 eigenvectors").bytes, with_pvf);
  k = base;
  k.test_max_steps = 3000;
  EXPECT_GT(estimate(k).record_bytes, estimate(base).record_bytes);
  // grid_from_samples sizes the map from the readings: 5 sqrt(510) = 113 units.
  k = base;
  k.som = "grid_from_samples = true";
  EXPECT_GT(item_naming(estimate(k), "SOM").bytes, item_naming(estimate(base), "SOM").bytes);
}

TEST(KheperaMemory, AFortyThousandSquareSomIsHuge) {
  KheperaJob k;
  k.series = 1;
  k.steps = 1600000000;  // the map may not have more units than readings
  k.som = "rows = 40000\ncols = 40000";
  const RunMemoryEstimate e = estimate(k);
  const MemoryItem& som = item_naming(e, "a 40000 x 40000 SOM");
  EXPECT_GT(som.bytes, 10e9);
  EXPECT_TRUE(std::isfinite(e.peak(1)));
  EXPECT_GT(e.peak(1), som.bytes);
  // The longest walk the table accepts.
  k.steps = 2147483646;
  k.som = "rows = 4\ncols = 5";
  EXPECT_GT(estimate(k).peak(1), 100e9);
  EXPECT_TRUE(std::isfinite(estimate(k).peak(1)));
}

// The copy scheme forms no state-action feature table: a fit holds its state
// kernels (a dense readings x p table of compressed entries at most, shared with
// the fit of the other solver). The estimate counts that, never less, and not
// the m-row feature table it no longer forms.
TEST(KheperaMemory, CountsTheKernelTableTheCopySchemeAllocates) {
  KheperaJob k;
  k.kernels = "[5, 10]";
  k.scheme = "copy";
  const RunMemoryEstimate e = estimate(k);
  const double readings = 10.0 * (50.0 + 1.0);
  const double table = readings * 10.0 * 12.0 + (readings + 1.0) * 4.0;  // entries, row pointers
  const MemoryItem& fit = item_naming(e, "the state kernels of a fit with 10 kernels");
  EXPECT_TRUE(fit.per_fit);
  EXPECT_GE(fit.bytes, table);
  // Not the copy basis' feature table (4 actions: 5 tables' worth with the kernels).
  EXPECT_LT(fit.bytes, 2.0 * table);
  // The shift scheme does form its feature table (m rows per reading).
  k.scheme = "shift";
  EXPECT_GE(item_naming(estimate(k), "the kernel and feature tables of a fit").bytes, 5.0 * table);
}

TEST(KheperaMemory, CoversWhatARunRecordHolds) {
  const JobSpec job = parse(KheperaJob{});
  const RunMemoryEstimate e = find_task("khepera")->estimate_run_bytes(job);
  const double held = record_bytes(compute_run(job, 0));
  EXPECT_GE(e.record_bytes, held);
  EXPECT_LT(e.record_bytes, 10.0 * held);
}

}  // namespace
}  // namespace ggk::engine
