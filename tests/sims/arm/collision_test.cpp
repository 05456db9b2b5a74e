#include "sims/arm/collision.hpp"

#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "sims/arm/arm.hpp"
#include "sims/arm/arm_geometry.hpp"
#include "sims/arm/collision.hpp"
#include "sims/arm/kinematics.hpp"

namespace ggk::sims::arm {
namespace {

TEST(ArmCollision, SegmentAgainstRectangle) {
  const Rectangle box{{1.0, 1.0}, {2.0, 3.0}};
  EXPECT_TRUE(segment_meets_rectangle({0.0, 2.0}, {3.0, 2.0}, box));   // straight through
  EXPECT_TRUE(segment_meets_rectangle({1.5, 0.0}, {1.5, 1.0}, box));   // ends on the bottom edge
  EXPECT_TRUE(segment_meets_rectangle({0.0, 0.0}, {1.0, 1.0}, box));   // ends on a corner
  EXPECT_TRUE(segment_meets_rectangle({0.0, 4.0}, {4.0, 0.0}, box));   // crosses a corner region
  EXPECT_TRUE(segment_meets_rectangle({1.2, 1.5}, {1.8, 2.5}, box));   // wholly inside
  EXPECT_TRUE(segment_meets_rectangle({1.5, 2.0}, {5.0, 7.0}, box));   // starts inside
  EXPECT_TRUE(segment_meets_rectangle({0.0, 3.0}, {3.0, 3.0}, box));   // along the top edge
  EXPECT_TRUE(segment_meets_rectangle({1.5, 1.5}, {1.5, 1.5}, box));   // a point inside
  EXPECT_FALSE(segment_meets_rectangle({0.0, 0.0}, {0.9, 0.9}, box));  // stops short
  EXPECT_FALSE(segment_meets_rectangle({0.0, 3.5}, {3.0, 3.5}, box));  // parallel above
  EXPECT_FALSE(segment_meets_rectangle({0.0, 2.5}, {1.0, 4.5}, box));  // passes the corner (1, 3)
  EXPECT_FALSE(segment_meets_rectangle({2.5, 0.0}, {2.5, 4.0}, box));  // parallel, right of it
  EXPECT_FALSE(segment_meets_rectangle({0.5, 0.5}, {0.5, 0.5}, box));  // a point outside
  // The segment's line meets the box, the segment does not.
  EXPECT_FALSE(segment_meets_rectangle({3.0, 2.0}, {4.0, 2.0}, box));
}

TEST(ArmCollision, SegmentAgainstDisc) {
  const Disc disc{{0.0, 0.0}, 1.0};
  EXPECT_TRUE(segment_meets_disc({-2.0, 0.0}, {2.0, 0.0}, disc));     // through the centre
  EXPECT_TRUE(segment_meets_disc({-2.0, 1.0}, {2.0, 1.0}, disc));     // tangent at (0, 1)
  EXPECT_TRUE(segment_meets_disc({0.2, 0.2}, {0.3, -0.1}, disc));     // inside
  EXPECT_TRUE(segment_meets_disc({0.5, 0.0}, {5.0, 5.0}, disc));      // starts inside
  EXPECT_TRUE(segment_meets_disc({1.0, 0.0}, {3.0, 0.0}, disc));      // starts on the boundary
  EXPECT_FALSE(segment_meets_disc({-2.0, 1.01}, {2.0, 1.01}, disc));  // just above
  // Nearest point of the line is (0, 0.5), but the segment ends at x = 1.5.
  EXPECT_FALSE(segment_meets_disc({1.5, 0.5}, {3.0, 0.5}, disc));
  // Diagonal passing at distance sqrt(2) - 0.5 * sqrt(2) = 0.707 < 1 vs one at 1.06.
  EXPECT_TRUE(segment_meets_disc({1.0, 0.0}, {0.0, 1.0}, disc));
  EXPECT_FALSE(segment_meets_disc({1.5, 0.0}, {0.0, 1.5}, disc));
  EXPECT_TRUE(segment_meets_disc({0.6, 0.6}, {0.6, 0.6}, disc));   // a point inside
  EXPECT_FALSE(segment_meets_disc({0.8, 0.8}, {0.8, 0.8}, disc));  // a point outside
}

TEST(ArmCollision, EitherLinkCollidesAndTheEndEffectorTouchesTheObject) {
  ArmGeometry geometry;  // links 1 and 1 from the origin
  geometry.object = {{1.0, 1.0}, 0.1};
  // Straight up: link 1 from (0, 0) to (0, 1), link 2 from (0, 1) to (0, 2).
  const ArmPose up = forward_kinematics(geometry, 90.0, 0.0);
  EXPECT_FALSE(arm_collides(geometry, up));

  geometry.obstacles = {Rectangle{{-0.1, 0.4}, {0.1, 0.6}}};  // across link 1
  EXPECT_TRUE(arm_collides(geometry, up));
  geometry.obstacles = {Disc{{0.05, 1.5}, 0.1}};  // across link 2
  EXPECT_TRUE(arm_collides(geometry, up));
  geometry.obstacles = {Disc{{0.5, 1.5}, 0.1}, Rectangle{{-1.0, 2.1}, {1.0, 3.0}}};  // beside
  EXPECT_FALSE(arm_collides(geometry, up));
  EXPECT_FALSE(touches_object(geometry, up));

  // Up, forearm to the right: the end effector is at (1, 1), the object's centre.
  const ArmPose reach = forward_kinematics(geometry, 90.0, -90.0);
  EXPECT_TRUE(touches_object(geometry, reach));
  geometry.object = {{1.25, 1.0}, 0.25};  // on its boundary (exact in binary)
  EXPECT_TRUE(touches_object(geometry, reach));
  geometry.object = {{1.26, 1.0}, 0.25};
  EXPECT_FALSE(touches_object(geometry, reach));
  // The object is no obstacle: link 2 may sweep over it.
  geometry.obstacles.clear();
  geometry.object = {{0.5, 1.0}, 0.1};
  EXPECT_FALSE(arm_collides(geometry, reach));
}
}  // namespace
}  // namespace ggk::sims::arm
