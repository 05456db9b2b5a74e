#include "engine/run/progress.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace ggk::engine
