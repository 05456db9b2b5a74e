#include "sims/khepera/khepera.hpp"

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

#include "sims/khepera/khepera_test_helpers.hpp"

namespace ggk::sims::khepera {
namespace {

using kernels::RandomStream;

constexpr double kPi = std::numbers::pi;

using namespace test_helpers;

// Distance from `origin` along the ray of angle `angle` to the line x = wall_x,
// or +infinity when the ray points away or the hit lies beyond 10 cm.
double hand_distance_to_vertical_wall(double origin_x, double angle, double wall_x) {
  const double c = std::cos(angle);
  if (c <= 0.0) return kNoHit;
  const double d = (wall_x - origin_x) / c;
  return d <= 10.0 ? d : kNoHit;
}

TEST(KheperaSensors, FacingAWallMatchesHandComputedReadings) {
  // Robot at (x, 50) facing +x towards the wall x = 60; every sensor's three rays
  // meet the wall line (if at all) at (60 - mount_x) / cos(angle).
  const Khepera robot(open_config({kWallAt60}, {40.0, 50.0, 0.0}));
  const double side = 15.0 * kPi / 180.0;
  for (double gap : {1.0, 2.0, 3.5, 6.0, 9.0, 9.8, 10.0, 10.5, 14.0}) {
    // gap = distance from the front sensors s2, s3 (x = 1.6) to the wall.
    const Pose pose{60.0 - 1.6 - gap, 50.0, 0.0};
    ASSERT_FALSE(robot.collides(pose)) << gap;
    const Readings readings = robot.sense_noiseless(pose);
    for (std::size_t i = 0; i < kKheperaSensors.size(); ++i) {
      const IrSensor& s = kKheperaSensors[i];
      const double heading = s.heading_deg * kPi / 180.0;
      const double mount_x = pose.x + s.x;
      const double left = hand_distance_to_vertical_wall(mount_x, heading + side, 60.0);
      const double centre = hand_distance_to_vertical_wall(mount_x, heading, 60.0);
      const double right = hand_distance_to_vertical_wall(mount_x, heading - side, 60.0);
      const double expected = std::clamp(
          hand_f(left) + hand_f(centre) + hand_f(right) - 2.0 * hand_f(centre / std::cos(side)),
          0.0, 1023.0);
      EXPECT_NEAR(readings[i], expected, 1e-9) << "gap " << gap << " sensor " << i;
      const SensorRays rays = robot.sensor_rays(pose, static_cast<std::int32_t>(i));
      if (std::isinf(centre)) {
        EXPECT_TRUE(std::isinf(rays.centre));
      } else {
        EXPECT_NEAR(rays.centre, centre, 1e-9);
      }
    }
    // The front sensors face the wall squarely and read exactly F(gap).
    EXPECT_NEAR(readings[2], gap <= 10.0 ? hand_f(gap) : 0.0, 1e-9) << gap;
    EXPECT_NEAR(readings[3], readings[2], 1e-9);
    // The back sensors look away.
    EXPECT_EQ(readings[6], 0.0);
    EXPECT_EQ(readings[7], 0.0);
  }
  // Spot values, from the formula by hand: F(1) = 7428 / 9.8, F(3.5) = 7428 / 25.55.
  EXPECT_NEAR(robot.sense_noiseless({57.4, 50.0, 0.0})[2], 7428.0 / 9.8, 1e-9);
  EXPECT_NEAR(robot.sense_noiseless({54.9, 50.0, 0.0})[2], 7428.0 / 25.55, 1e-9);
  // s1 (45 degrees) sees the wall at 1.3 cm nearer mount x, through three oblique rays.
  const double g = 60.0 - (54.9 + 1.3);
  const double expected_s1 = hand_f(g / std::cos(60.0 * kPi / 180.0)) +
                             hand_f(g / std::cos(45.0 * kPi / 180.0)) +
                             hand_f(g / std::cos(30.0 * kPi / 180.0)) -
                             2.0 * hand_f(g / std::cos(45.0 * kPi / 180.0) / std::cos(side));
  EXPECT_NEAR(robot.sense_noiseless({54.9, 50.0, 0.0})[1], expected_s1, 1e-9);
  EXPECT_GT(expected_s1, 0.0);
}

TEST(KheperaSensors, ReadingsAreClampedToTheSensorRange) {
  KheperaConfig config = open_config({kWallAt60});
  config.sensors.max_reading = 500.0;
  const Khepera robot(config);
  const Readings near = robot.sense_noiseless({57.4, 50.0, 0.0});
  EXPECT_EQ(near[2], 500.0);  // F(1) = 758 before clamping
  // A post seen only by the centre ray is over-corrected below 0 and clamped.
  const Khepera post(open_config({Disc{{55.0, 50.6}, 0.1}}, {40.0, 50.0, 0.0}));
  const Pose facing{55.0 - 0.1 - 3.0 - 1.6, 50.0, 0.0};
  EXPECT_NEAR(post.sensor_rays(facing, 2).centre, 3.0, 1e-9);
  EXPECT_TRUE(std::isinf(post.sensor_rays(facing, 2).left));
  EXPECT_EQ(post.sense_noiseless(facing)[2], 0.0);
  // With additive noise, readings stay in [0, 1023] and far from anything often hit 0.
  KheperaConfig noisy = open_config({});
  noisy.sensors.noise_model = SensorNoiseModel::additive;
  noisy.sensors.noise_sd = 20.0;
  const Khepera lonely(noisy);
  RandomStream random(3, 0, 0);
  std::int32_t zeros = 0;
  for (int t = 0; t < 1000; ++t) {
    for (double r : lonely.sense({50.0, 50.0, 0.0}, random)) {
      EXPECT_GE(r, 0.0);
      EXPECT_LE(r, 1023.0);
      zeros += r == 0.0;
    }
  }
  EXPECT_NEAR(zeros / 8000.0, 0.5, 0.03);  // half of N(0, 20) is clamped to 0
}

TEST(KheperaSensors, BeyondRangeReadsZero) {
  const Khepera robot(open_config({kWallAt60}));
  const Readings far = robot.sense_noiseless({60.0 - 1.6 - 10.01, 50.0, 0.0});
  for (double r : far) EXPECT_EQ(r, 0.0);
  const Readings edge = robot.sense_noiseless({60.0 - 1.6 - 9.99, 50.0, 0.0});
  EXPECT_NEAR(edge[2], hand_f(9.99), 1e-9);
  EXPECT_GT(edge[2], 50.0);
  // An empty world reads 0 everywhere, facing anywhere.
  const Khepera empty(open_config({}));
  for (double heading : {-3.0, -1.0, 0.0, 0.5, 2.0})
    for (double r : empty.sense_noiseless({30.0, 70.0, heading})) EXPECT_EQ(r, 0.0);
}

TEST(KheperaSensors, NoReadingThroughWalls) {
  // A disc 1 cm behind the wall x = 60, right in front of s2 and s3.
  const Shape disc_behind = Disc{{64.0, 50.0}, 3.0};
  const Khepera walled(open_config({kWallAt60, disc_behind}));
  const Khepera wall_only(open_config({kWallAt60}));
  const Khepera disc_only(open_config({disc_behind}));
  for (double gap : {1.0, 3.0, 6.0}) {
    const Pose pose{60.0 - 1.6 - gap, 50.0, 0.0};
    EXPECT_EQ(walled.sense_noiseless(pose), wall_only.sense_noiseless(pose)) << gap;
    // Without the wall the disc is in range and reads differently.
    EXPECT_NE(disc_only.sense_noiseless(pose), wall_only.sense_noiseless(pose)) << gap;
  }
  // The same through a box's edge: an obstacle inside a rectangle is invisible.
  const Shape box = Rectangle{{60.0, 40.0}, {70.0, 60.0}};
  const Khepera boxed(open_config({box, Disc{{61.0, 50.0}, 0.5}}));
  const Khepera box_only(open_config({box}));
  EXPECT_EQ(boxed.sense_noiseless({55.0, 50.0, 0.0}), box_only.sense_noiseless({55.0, 50.0, 0.0}));
}

// `shape` turned by `angle` (radians) about `pivot`.
Point2 turn(Point2 p, Point2 pivot, double angle) {
  return pivot + rotated(p - pivot, std::cos(angle), std::sin(angle));
}
Shape turn(const Shape& shape, Point2 pivot, double angle) {
  if (const auto* s = std::get_if<Segment>(&shape))
    return Segment{turn(s->a, pivot, angle), turn(s->b, pivot, angle)};
  if (const auto* d = std::get_if<Disc>(&shape))
    return Disc{turn(d->center, pivot, angle), d->radius};
  if (const auto* r = std::get_if<Rectangle>(&shape))
    return RotatedRectangle{turn(0.5 * (r->min + r->max), pivot, angle), r->max.x - r->min.x,
                            r->max.y - r->min.y, angle * 180.0 / kPi};
  const auto& q = std::get<RotatedRectangle>(shape);
  return RotatedRectangle{turn(q.center, pivot, angle), q.width, q.height,
                          q.angle_deg + angle * 180.0 / kPi};
}

TEST(KheperaSensors, RotatingRobotAndWorldTogetherKeepsTheReadings) {
  const std::vector<Shape> shapes = {Segment{{10.0, 10.0}, {90.0, 10.0}},
                                     Segment{{90.0, 10.0}, {90.0, 90.0}},
                                     Segment{{90.0, 90.0}, {10.0, 90.0}},
                                     Segment{{10.0, 90.0}, {10.0, 10.0}},
                                     Rectangle{{30.0, 30.0}, {42.0, 38.0}},
                                     RotatedRectangle{{65.0, 40.0}, 14.0, 4.0, 25.0},
                                     Disc{{50.0, 65.0}, 6.0},
                                     Segment{{20.0, 70.0}, {35.0, 60.0}}};
  const Point2 pivot{50.0, 50.0};
  const Khepera original(open_config(shapes));
  RandomStream random(11, 0, 0);
  for (double angle : {0.37, kPi / 2.0, 2.0, -2.9}) {
    std::vector<Shape> turned;
    for (const Shape& s : shapes) turned.push_back(turn(s, pivot, angle));
    const Khepera rotated_robot(open_config(turned, {pivot.x, pivot.y, 0.0}));
    std::int32_t seen = 0;
    for (int i = 0; i < 300; ++i) {
      const Pose pose{random.uniform(12.0, 88.0), random.uniform(12.0, 88.0),
                      random.uniform(-kPi, kPi)};
      if (original.collides(pose)) continue;
      const Point2 centre = turn({pose.x, pose.y}, pivot, angle);
      const Pose turned_pose{centre.x, centre.y, wrap_angle(pose.heading + angle)};
      ASSERT_FALSE(rotated_robot.collides(turned_pose));
      const Readings a = original.sense_noiseless(pose);
      const Readings b = rotated_robot.sense_noiseless(turned_pose);
      for (std::size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(a[k], b[k], 1e-7) << i << " " << k;
      for (double r : a) seen += r > 0.0;
    }
    EXPECT_GT(seen, 100);  // the poses do see the obstacles
  }
}

TEST(KheperaStep, ForwardInFreeSpaceEarnsOneAndMovesAboutAStep) {
  const Khepera robot{KheperaConfig{}};  // empty 1 m box, default noise
  RandomStream random(1, 0, 0);
  const Pose pose{50.0, 50.0, 0.7};
  for (int i = 0; i < 200; ++i) {
    const StepResult forward = robot.step(pose, kForward, random);
    EXPECT_EQ(forward.reward, 1.0);
    EXPECT_FALSE(forward.collided);
    const double moved = std::hypot(forward.next_pose.x - pose.x, forward.next_pose.y - pose.y);
    EXPECT_GE(moved, 1.5 * 0.95 - 1e-9);
    EXPECT_LT(moved, 1.5 * 1.05);
    // Ahead, give or take the curve of unequal wheels.
    const double bearing = std::atan2(forward.next_pose.y - pose.y, forward.next_pose.x - pose.x);
    EXPECT_LT(std::abs(bearing - pose.heading), 0.02);
    for (double r : forward.observation) EXPECT_LE(r, 100.0);  // noise only

    const StepResult back = robot.step(pose, kBackward, random);
    EXPECT_EQ(back.reward, 0.0);
    EXPECT_NEAR(std::hypot(back.next_pose.x - pose.x, back.next_pose.y - pose.y), 1.5, 0.08);
    const StepResult left = robot.step(pose, kRotateLeft, random);
    EXPECT_EQ(left.reward, 0.0);
    EXPECT_NEAR(left.next_pose.heading - pose.heading, 15.0 * kPi / 180.0,
                0.05 * 15.0 * kPi / 180.0);
    EXPECT_LT(std::hypot(left.next_pose.x - pose.x, left.next_pose.y - pose.y), 0.05);
    const StepResult right = robot.step(pose, kRotateRight, random);
    EXPECT_EQ(right.reward, 0.0);
    EXPECT_NEAR(right.next_pose.heading - pose.heading, -15.0 * kPi / 180.0,
                0.05 * 15.0 * kPi / 180.0);
  }
  EXPECT_THROW(robot.step(pose, 4, random), std::out_of_range);
  EXPECT_THROW(robot.step(pose, -1, random), std::out_of_range);
  EXPECT_EQ(action_name(kForward), "forward");
  EXPECT_EQ(action_name(kBackward), "backward");
  EXPECT_THROW(action_name(7), std::out_of_range);
}

TEST(KheperaStep, AMoveIntoAWallIsUndoneAndCostsTwo) {
  const Khepera robot(open_config({kWallAt60}, {40.0, 50.0, 0.0}));
  RandomStream random(2, 0, 0);
  // The body is 0.5 cm from the wall: a 1.5 cm step forward would overlap it.
  const Pose facing{60.0 - 2.6 - 0.5, 50.0, 0.0};
  const StepResult forward = robot.step(facing, kForward, random);
  EXPECT_TRUE(forward.collided);
  EXPECT_EQ(forward.reward, -2.0);
  EXPECT_EQ(forward.next_pose, facing);
  EXPECT_EQ(forward.observation, robot.sense_noiseless(facing));  // noise off
  // Backing into it: the same.
  const Pose backing{facing.x, facing.y, kPi - 1e-9};
  const StepResult backward = robot.step(backing, kBackward, random);
  EXPECT_TRUE(backward.collided);
  EXPECT_EQ(backward.reward, -2.0);
  EXPECT_EQ(backward.next_pose, backing);
  // Turning on the spot and backing away are fine.
  EXPECT_FALSE(robot.step(facing, kRotateLeft, random).collided);
  const StepResult away = robot.step(facing, kBackward, random);
  EXPECT_FALSE(away.collided);
  EXPECT_EQ(away.reward, 0.0);
  EXPECT_NEAR(away.next_pose.x, facing.x - 1.5, 1e-12);
  // 1.6 cm of room: the step fits.
  const StepResult fits = robot.step({60.0 - 2.6 - 1.6, 50.0, 0.0}, kForward, random);
  EXPECT_FALSE(fits.collided);
  EXPECT_EQ(fits.reward, 1.0);
}

TEST(KheperaStep, SubStepsCatchAGrazedCorner) {
  // A thin post whose tip the body sweeps past mid-step but clears at both ends:
  // the body at 1.5 cm ahead and at the start is 2.6 from the post, while the
  // swept body passes it at 2.49.
  const double lateral = 2.55;  // between sqrt(2.6^2 - 0.75^2) = 2.489 and 2.6
  const Shape tip = Segment{{50.75, 50.0 + lateral}, {50.75, 60.0}};
  KheperaConfig one = open_config({tip}, {40.0, 40.0, 0.0});
  one.motion.collision_substeps = 1;
  KheperaConfig four = open_config({tip}, {40.0, 40.0, 0.0});
  RandomStream random(4, 0, 0);
  const Pose pose{50.0, 50.0, 0.0};
  EXPECT_FALSE(Khepera(one).step(pose, kForward, random).collided);
  EXPECT_TRUE(Khepera(four).step(pose, kForward, random).collided);
}

TEST(KheperaStep, WheelFactorsAreTheStreamsUniformsInOrder) {
  // Recover each wheel's travel from the pose change (exact inverse of drive) and
  // compare with the factors the stream gives in the documented order.
  KheperaConfig config;
  config.sensors.noise_fraction = 0.0;
  const Khepera robot(config);
  const double b = config.body.wheel_base;
  RandomStream random(17, 3, 1);
  RandomStream replay(17, 3, 1);
  const Pose pose{50.0, 50.0, 0.3};
  const std::int32_t n = 20000;
  double sum[2] = {0.0, 0.0};
  double sum_squares[2] = {0.0, 0.0};
  double sum_product = 0.0;
  for (std::int32_t i = 0; i < n; ++i) {
    const std::int32_t action = i % kNumActions;
    const StepResult result = robot.step(pose, action, random);
    const WheelTravel command = wheel_command(config.motion, b, action);
    const double turn = wrap_angle(result.next_pose.heading - pose.heading);
    const double half = 0.5 * turn;
    // drive() moves the centre distance * sin(h) / h along the mean heading.
    const double along = (result.next_pose.x - pose.x) * std::cos(pose.heading + half) +
                         (result.next_pose.y - pose.y) * std::sin(pose.heading + half);
    const double distance = along / (half == 0.0 ? 1.0 : std::sin(half) / half);
    const double left = distance - 0.5 * b * turn;
    const double right = distance + 0.5 * b * turn;
    const double factors[2] = {left / command.left, right / command.right};
    EXPECT_NEAR(factors[0], replay.uniform(0.95, 1.05), 1e-6) << i;
    EXPECT_NEAR(factors[1], replay.uniform(0.95, 1.05), 1e-6) << i;
    for (int w = 0; w < 2; ++w) {
      EXPECT_GE(factors[w], 0.95 - 1e-9);
      EXPECT_LT(factors[w], 1.05 + 1e-9);
      sum[w] += factors[w];
      sum_squares[w] += factors[w] * factors[w];
    }
    sum_product += (factors[0] - 1.0) * (factors[1] - 1.0);
  }
  // U[0.95, 1.05): mean 1, variance 0.1^2 / 12; the wheels independent.
  const double variance = 0.01 / 12.0;
  for (int w = 0; w < 2; ++w) {
    const double mean = sum[w] / n;
    EXPECT_NEAR(mean, 1.0, 4.0 * std::sqrt(variance / n));
    EXPECT_NEAR(sum_squares[w] / n - mean * mean, variance, 0.05 * variance);
  }
  EXPECT_NEAR(sum_product / n / variance, 0.0, 0.05);
}

// A random walk of `steps` random actions from a random free pose, all from one
// stream; returns every step's result.
std::vector<StepResult> random_walk(const Khepera& robot, RandomStream random, std::int32_t steps) {
  std::vector<StepResult> results;
  Pose pose = robot.sample_free_pose(random);
  for (std::int32_t t = 0; t < steps; ++t) {
    const auto action = static_cast<std::int32_t>(random.uniform_index(kNumActions));
    results.push_back(robot.step(pose, action, random));
    pose = results.back().next_pose;
  }
  return results;
}

KheperaConfig cluttered_config() {
  KheperaConfig config;
  config.arena.max = {60.0, 60.0};
  config.arena.start = {5.0, 5.0, 0.0};
  config.arena.obstacles = {Rectangle{{12.0, 10.0}, {26.0, 22.0}}, Disc{{38.0, 18.0}, 4.0},
                            RotatedRectangle{{40.0, 45.0}, 22.0, 5.0, 30.0},
                            Segment{{60.0, 30.0}, {45.0, 30.0}}};
  return config;
}

void expect_same(const std::vector<StepResult>& a, const std::vector<StepResult>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t t = 0; t < a.size(); ++t) {
    EXPECT_EQ(a[t].observation, b[t].observation) << t;
    EXPECT_EQ(a[t].next_pose, b[t].next_pose) << t;
    EXPECT_EQ(a[t].reward, b[t].reward) << t;
    EXPECT_EQ(a[t].collided, b[t].collided) << t;
  }
}

TEST(KheperaStep, AFixedStreamGivesTheSameWalk) {
  const Khepera robot(cluttered_config());
  const std::vector<StepResult> a = random_walk(robot, RandomStream(8, 1, 2), 2000);
  const std::vector<StepResult> b = random_walk(robot, RandomStream(8, 1, 2), 2000);
  expect_same(a, b);
  const std::vector<StepResult> other = random_walk(robot, RandomStream(8, 2, 2), 2000);
  EXPECT_NE(a.front().next_pose, other.front().next_pose);
  std::int32_t collisions = 0;
  for (const StepResult& r : a) {
    collisions += r.collided;
    EXPECT_FALSE(robot.collides(r.next_pose));
  }
  EXPECT_GT(collisions, 10);  // the walk does meet obstacles
}

TEST(KheperaStep, ParallelWalksEqualSequentialOnes) {
  const Khepera robot(cluttered_config());
  constexpr std::int32_t kWalks = 64;
  std::vector<std::vector<StepResult>> sequential(kWalks);
  for (std::int32_t i = 0; i < kWalks; ++i)
    sequential[i] = random_walk(robot, RandomStream(99, static_cast<std::uint32_t>(i), 0), 300);
  std::vector<std::vector<StepResult>> parallel(kWalks);
  tbb::parallel_for(0, kWalks, [&](std::int32_t i) {
    parallel[i] = random_walk(robot, RandomStream(99, static_cast<std::uint32_t>(i), 0), 300);
  });
  for (std::int32_t i = 0; i < kWalks; ++i) expect_same(sequential[i], parallel[i]);
}

TEST(KheperaStep, FreePosesAreUniformOverFreeSpace) {
  const Khepera robot(cluttered_config());
  RandomStream random(6, 0, 0);
  RandomStream replay(6, 0, 0);
  double heading_sum = 0.0;
  std::int32_t left_half = 0;
  const std::int32_t n = 5000;
  for (std::int32_t i = 0; i < n; ++i) {
    const Pose pose = robot.sample_free_pose(random);
    EXPECT_FALSE(robot.collides(pose));
    EXPECT_GE(pose.x, 0.0);
    EXPECT_LT(pose.x, 60.0);
    EXPECT_GE(pose.heading, -kPi);
    EXPECT_LT(pose.heading, kPi);
    heading_sum += pose.heading;
    left_half += pose.x < 30.0;
    EXPECT_EQ(pose, robot.sample_free_pose(replay));
  }
  EXPECT_NEAR(heading_sum / n, 0.0, 4.0 * kPi / std::sqrt(3.0 * n));
  // By symmetry of rejection sampling: the share of the left half is the share of
  // its free area, estimated on a fine grid.
  std::int32_t free_left = 0;
  std::int32_t free_all = 0;
  for (double x = 0.05; x < 60.0; x += 0.1) {
    for (double y = 0.05; y < 60.0; y += 0.1) {
      if (robot.collides({x, y, 0.0})) continue;
      ++free_all;
      free_left += x < 30.0;
    }
  }
  const double p = static_cast<double>(free_left) / free_all;
  EXPECT_NEAR(static_cast<double>(left_half) / n, p, 4.0 * std::sqrt(p * (1 - p) / n));
}
}  // namespace
}  // namespace ggk::sims::khepera
