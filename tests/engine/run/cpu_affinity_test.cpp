#include "engine/run/cpu_affinity.hpp"

#include <gtest/gtest.h>
#include <sched.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace ggk::engine {
namespace {

TEST(CpuAffinity, describes_cpu_lists_as_ranges) {
  EXPECT_EQ(describe_cpus(std::vector<std::int32_t>{0, 1, 2, 3, 8, 10, 11}), "0-3,8,10-11");
  EXPECT_EQ(describe_cpus(std::vector<std::int32_t>{5}), "5");
  EXPECT_EQ(describe_cpus(std::vector<std::int32_t>{}), "");
}

TEST(CpuAffinity, warns_only_when_threads_exceed_the_mask) {
  const std::vector<std::int32_t> one{3}, four{0, 1, 2, 3};
  EXPECT_FALSE(oversubscription_warning(0, one));  // oneTBB's default follows the mask
  EXPECT_FALSE(oversubscription_warning(1, one));
  EXPECT_FALSE(oversubscription_warning(4, four));
  EXPECT_FALSE(oversubscription_warning(16, {}));  // mask unknown
  const auto warning = oversubscription_warning(16, one);
  ASSERT_TRUE(warning);
  EXPECT_NE(warning->find("-j 16 starts 16 compute threads, but this process may run on 1 CPU "
                          "(its affinity mask: 3)"),
            std::string::npos);
  EXPECT_NE(warning->find("srun --cpus-per-task"), std::string::npos);
  ASSERT_TRUE(oversubscription_warning(5, four));
  EXPECT_NE(oversubscription_warning(5, four)->find("on 4 CPUs (its affinity mask: 0-3)"),
            std::string::npos);
}

TEST(CpuAffinity, reads_this_process_mask) {
  const auto cpus = affinity_cpus();
  ASSERT_FALSE(cpus.empty());
  EXPECT_TRUE(std::is_sorted(cpus.begin(), cpus.end()));
  cpu_set_t set;
  CPU_ZERO(&set);
  ASSERT_EQ(sched_getaffinity(0, sizeof(set), &set), 0);
  EXPECT_EQ(static_cast<int>(cpus.size()), CPU_COUNT(&set));
}

}  // namespace
}  // namespace ggk::engine
