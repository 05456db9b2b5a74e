#include "engine/run/progress.hpp"

#include <gtest/gtest.h>

namespace ggk::engine {
namespace {

TEST(Progress, EtaIsUnknownUntilTheFirstRunEnds) {
  EXPECT_EQ(eta_text(0, 10, 30.0), "--");
  EXPECT_EQ(eta_text(1, 10, 30.0), "270s");
  EXPECT_EQ(eta_text(10, 10, 30.0), "0s");
}

}  // namespace
}  // namespace ggk::engine
