// arena_arrays (engine/tasks/khepera/khepera_arena.hpp): the geometry of
// Fig. 4(a) for the default arena, against the simulator: shapes, the start
// pose, the noiseless readings and every sensor ray's length and hit flag.

#include "engine/tasks/khepera/khepera_arena.hpp"

#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::engine {
namespace {

namespace khepera = sims::khepera;

TEST(KheperaArena, ArraysMatchTheSimulator) {
  const khepera::Khepera robot{khepera::KheperaConfig{}};
  std::map<std::string, NamedArray> arrays;
  for (NamedArray& a : arena_arrays(robot)) arrays[a.name] = a;
  ASSERT_EQ(arrays.size(), 10u);
  for (const auto& entry : arrays) {
    std::int64_t size = 1;
    for (const std::int64_t extent : entry.second.shape) size *= extent;
    EXPECT_EQ(size, static_cast<std::int64_t>(entry.second.values.size())) << entry.first;
  }
  const khepera::Pose start = robot.start_pose();
  EXPECT_EQ(arrays.at("arena/start").values,
            (std::vector<double>{start.x, start.y, start.heading}));
  EXPECT_EQ(arrays.at("robot/radius").values, (std::vector<double>{robot.config().body.radius}));
  EXPECT_EQ(arrays.at("robot/sensors").shape, (std::vector<std::int64_t>{8, 3}));
  const khepera::Readings clean = robot.sense_noiseless(start);
  EXPECT_EQ(arrays.at("robot/start_readings").values,
            std::vector<double>(clean.begin(), clean.end()));
  const NamedArray& rays = arrays.at("robot/start_rays");
  ASSERT_EQ(rays.shape, (std::vector<std::int64_t>{24, 5}));
  const double range = robot.config().sensors.range;
  for (std::int32_t i = 0; i < khepera::kNumSensors; ++i) {
    const khepera::SensorRays hit = robot.sensor_rays(start, i);
    const double distances[3] = {hit.left, hit.centre, hit.right};
    for (std::size_t k = 0; k < 3; ++k) {
      const double* ray = &rays.values[(3 * static_cast<std::size_t>(i) + k) * 5];
      const bool seen = distances[k] <= range;
      EXPECT_EQ(ray[4], seen ? 1.0 : 0.0);
      EXPECT_NEAR(std::hypot(ray[2] - ray[0], ray[3] - ray[1]), seen ? distances[k] : range, 1e-9);
    }
  }
}

}  // namespace
}  // namespace ggk::engine
