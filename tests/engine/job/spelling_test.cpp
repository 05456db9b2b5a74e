#include "engine/job/spelling.hpp"

#include <array>

#include <gtest/gtest.h>

namespace ggk::engine {
namespace {

TEST(EditDistance, KnownValues) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("abc", ""), 3u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("gamma", "gamma"), 0u);
  EXPECT_EQ(edit_distance("gama", "gamma"), 1u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("flaw", "lawn"), 2u);
  EXPECT_EQ(edit_distance("lstd", "lstdq"), 1u);
  EXPECT_EQ(edit_distance("sigma", "simga"), 1u);  // one swap
  EXPECT_EQ(edit_distance("rusn", "runs"), 1u);
  EXPECT_EQ(edit_distance("ca", "abc"), 3u);  // no edits of an already swapped pair
}

TEST(ClosestSpelling, SuggestsOnlyPlausibleMisspellings) {
  constexpr std::array<std::string_view, 4> keys = {"gamma", "max_iterations", "fold_duplicates",
                                                    "min_rcond"};
  EXPECT_EQ(closest_spelling("gama", keys), "gamma");
  EXPECT_EQ(closest_spelling("Gamma", keys), "gamma");
  EXPECT_EQ(closest_spelling("max_iteration", keys), "max_iterations");
  EXPECT_EQ(closest_spelling("max_iter", keys), "max_iterations");  // a prefix
  EXPECT_EQ(closest_spelling("min_rcnd", keys), "min_rcond");
  EXPECT_EQ(closest_spelling("gamam", keys), "gamma");
  EXPECT_FALSE(closest_spelling("alpha", keys).has_value());
  EXPECT_FALSE(closest_spelling("x", keys).has_value());
  EXPECT_FALSE(closest_spelling("", keys).has_value());
}

}  // namespace
}  // namespace ggk::engine
