#include "sims/khepera/world.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include "sims/khepera/khepera.hpp"

namespace ggk::sims::khepera {
namespace {

using kernels::RandomStream;

TEST(KheperaWorld, RayDistancesToEachShape) {
  Arena arena;
  arena.walled = false;
  arena.obstacles = {Segment{{10.0, 0.0}, {10.0, 20.0}}, Rectangle{{20.0, 40.0}, {30.0, 50.0}},
                     RotatedRectangle{{70.0, 70.0}, 10.0, 10.0, 45.0}, Disc{{50.0, 20.0}, 2.0}};
  const World world(arena, 10.0);
  EXPECT_EQ(world.num_segments(), 1 + 4 + 4);
  EXPECT_EQ(world.num_discs(), 1);
  EXPECT_EQ(world.num_boxes(), 2);
  EXPECT_NEAR(world.ray_distance({5.0, 10.0}, {1.0, 0.0}, 10.0), 5.0, 1e-12);
  EXPECT_EQ(world.ray_distance({5.0, 10.0}, {-1.0, 0.0}, 10.0), kNoHit);
  EXPECT_EQ(world.ray_distance({5.0, 25.0}, {1.0, 0.0}, 10.0), kNoHit);   // passes the end
  EXPECT_EQ(world.ray_distance({-6.0, 10.0}, {1.0, 0.0}, 10.0), kNoHit);  // beyond range
  EXPECT_NEAR(world.ray_distance({-6.0, 10.0}, {1.0, 0.0}, 16.0), 16.0, 1e-12);
  EXPECT_NEAR(world.ray_distance({25.0, 35.0}, {0.0, 1.0}, 10.0), 5.0, 1e-12);
  const double s = std::sqrt(0.5);
  // The rotated square's corner points at -x, at x = 70 - 5 sqrt(2); 0.5 above the
  // corner its upper-left face lies 0.5 further right.
  EXPECT_NEAR(world.ray_distance({60.0, 70.5}, {1.0, 0.0}, 10.0), 10.5 - 5.0 * std::sqrt(2.0),
              1e-9);
  // Its face towards (-1, -1) / sqrt(2) lies 5 from its centre.
  EXPECT_NEAR(world.ray_distance({64.0, 64.0}, {s, s}, 10.0), std::sqrt(72.0) - 5.0, 1e-9);
  EXPECT_NEAR(world.ray_distance({50.0, 14.0}, {0.0, 1.0}, 10.0), 4.0, 1e-12);
  EXPECT_EQ(world.ray_distance({50.0, 14.0}, {0.0, -1.0}, 10.0), kNoHit);
  EXPECT_NEAR(world.ray_distance({50.0, 20.0}, {0.0, 1.0}, 10.0), 2.0, 1e-12);  // from inside
  // Tangent-ish miss and a chord: from (46, 21) along +x the disc spans x = 50 -+ sqrt(3).
  EXPECT_NEAR(world.ray_distance({46.0, 21.0}, {1.0, 0.0}, 10.0), 4.0 - std::sqrt(3.0), 1e-12);
  EXPECT_EQ(world.ray_distance({46.0, 22.5}, {1.0, 0.0}, 10.0), kNoHit);
}

TEST(KheperaWorld, DiscOverlapOfEachShape) {
  Arena arena;
  arena.obstacles = {Segment{{10.0, 10.0}, {10.0, 20.0}}, Rectangle{{20.0, 40.0}, {30.0, 50.0}},
                     Disc{{50.0, 20.0}, 2.0}};
  const World world(arena, 10.0);
  EXPECT_TRUE(world.disc_overlaps({12.0, 15.0}, 2.6));
  EXPECT_FALSE(world.disc_overlaps({12.5, 15.0}, 2.5));  // touching is allowed
  EXPECT_TRUE(world.disc_overlaps({12.5, 15.0}, 2.5000001));
  EXPECT_TRUE(world.disc_overlaps({10.0, 22.5}, 2.6));  // past the segment's end
  EXPECT_FALSE(world.disc_overlaps({10.0, 22.7}, 2.6));
  EXPECT_TRUE(world.disc_overlaps({25.0, 45.0}, 2.6));  // deep inside the box
  EXPECT_TRUE(world.disc_overlaps({31.0, 45.0}, 2.6));
  EXPECT_FALSE(world.disc_overlaps({32.0, 52.0}, 2.8));  // the corner is 2 sqrt(2) away
  EXPECT_TRUE(world.disc_overlaps({32.0, 52.0}, 2.9));
  EXPECT_TRUE(world.disc_overlaps({54.5, 20.0}, 2.6));
  EXPECT_FALSE(world.disc_overlaps({54.7, 20.0}, 2.6));
  EXPECT_TRUE(world.disc_overlaps({1.0, 50.0}, 2.6));  // the box wall x = 0
  EXPECT_FALSE(world.disc_overlaps({3.0, 50.0}, 2.6));
}

TEST(KheperaWorld, GridGivesTheSameAnswersAsTestingEverything) {
  // reach 10 builds a fine grid; reach 1000 one cell listing everything.
  Arena arena;
  arena.obstacles = {Rectangle{{12.0, 10.0}, {26.0, 22.0}}, Disc{{38.0, 18.0}, 4.0},
                     RotatedRectangle{{54.0, 63.0}, 22.0, 5.0, 30.0},
                     Segment{{80.0, 18.0}, {64.0, 18.0}}, Disc{{62.0, 38.0}, 7.0}};
  arena.max = {80.0, 80.0};
  const World fine(arena, 10.0);
  const World coarse(arena, 1000.0);
  RandomStream random(5, 0, 0);
  std::int32_t hits = 0;
  std::int32_t overlaps = 0;
  for (int i = 0; i < 20000; ++i) {
    const Point2 origin{random.uniform(-1.0, 81.0), random.uniform(-1.0, 81.0)};
    const double angle = random.uniform(-std::numbers::pi, std::numbers::pi);
    const Point2 direction{std::cos(angle), std::sin(angle)};
    const double range = random.uniform(0.0, 10.0);
    const double d = fine.ray_distance(origin, direction, range);
    EXPECT_EQ(d, coarse.ray_distance(origin, direction, range));
    hits += d != kNoHit;
    const double radius = random.uniform(0.0, 10.0);
    const bool overlap = fine.disc_overlaps(origin, radius);
    EXPECT_EQ(overlap, coarse.disc_overlaps(origin, radius));
    overlaps += overlap;
  }
  EXPECT_GT(hits, 3000);
  EXPECT_GT(overlaps, 3000);
}
}  // namespace
}  // namespace ggk::sims::khepera
