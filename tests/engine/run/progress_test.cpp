#include "engine/run/progress.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace ggk::engine {
namespace {

TEST(Progress, EtaIsUnknownUntilTheFirstUnitEnds) {
  EXPECT_EQ(eta_text(0, 10, 30.0), "--");
  EXPECT_EQ(eta_text(1, 10, 30.0), "270s");
  EXPECT_EQ(eta_text(10, 10, 30.0), "0s");
}

// Inside a run the display moves with each fit (issue 36: a 52 s run showed
// "runs 0/1, 0.0 fits/s, eta --" throughout): fits done of all, their rate, and
// the ETA from them.
TEST(Progress, ALongRunShowsItsFitsAndAnEtaBeforeItEnds) {
  EXPECT_EQ(progress_text(0, 1, 10, 40, 5.0),
            "runs 0/1, fits 10/40, 2.0 fits/s, elapsed 5s, eta 15s");
  EXPECT_EQ(progress_text(0, 1, 0, 40, 5.0), "runs 0/1, fits 0/40, 0.0 fits/s, elapsed 5s, eta --");
  // More fits than the total (a grown study's units fit fewer points) never
  // show past it.
  EXPECT_EQ(progress_text(1, 1, 45, 40, 8.0),
            "runs 1/1, fits 40/40, 5.0 fits/s, elapsed 8s, eta 0s");
  // Not counted here (an MPI rank 0): runs only, the rate from whole runs.
  EXPECT_EQ(progress_text(2, 4, -1, 80, 10.0), "runs 2/4, 4.0 fits/s, elapsed 10s, eta 10s");
}

// Configurations of different cost (issue 36: with a cheap configuration done
// first, the ETA said 5 s with 15 s left): each configuration's units cost what
// its ended ones did, at the pace of the work so far.
TEST(Progress, TheEtaWeighsEachConfigurationByTheCostOfItsEndedUnits) {
  // 4 units of 1 s ended, 1 of 4 s of the dear configuration; 8 s on one thread.
  const std::vector<ConfigurationProgress> one_thread = {{4, 4, 4.0}, {4, 1, 4.0}};
  ASSERT_TRUE(weighted_seconds_left(one_thread, 8.0).has_value());
  EXPECT_DOUBLE_EQ(*weighted_seconds_left(one_thread, 8.0), 12.0);  // 3 x 4 s left
  EXPECT_EQ(eta_text(5, 8, 8.0), "5s");  // by units alone: 3 of 8 left at 1.6 s each
  // Two threads did the same work in 4 s: half the time left.
  EXPECT_DOUBLE_EQ(*weighted_seconds_left(one_thread, 4.0), 6.0);
  // A configuration none of whose units has ended costs the mean of those that did.
  const std::vector<ConfigurationProgress> unseen = {{2, 2, 2.0}, {3, 0, 0.0}};
  EXPECT_DOUBLE_EQ(*weighted_seconds_left(unseen, 2.0), 3.0);
  EXPECT_EQ(progress_text(2, 5, -1, 50, 2.0, weighted_seconds_left(unseen, 2.0)),
            "runs 2/5, 10.0 fits/s, elapsed 2s, eta 3s");
  // Before a unit ends, or with units ended that were never expected: none.
  EXPECT_FALSE(weighted_seconds_left(std::vector<ConfigurationProgress>{{3, 0, 0.0}}, 5.0));
  EXPECT_FALSE(weighted_seconds_left(std::vector<ConfigurationProgress>{{0, 2, 2.0}}, 5.0));
}

}  // namespace
}  // namespace ggk::engine
