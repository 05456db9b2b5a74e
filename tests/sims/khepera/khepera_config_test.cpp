#include "sims/khepera/khepera_config.hpp"

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

KheperaConfigError config_error_of(const KheperaConfig& config) {
  try {
    Khepera robot(config);
  } catch (const KheperaConfigError& error) {
    return error;
  }
  ADD_FAILURE() << "expected a KheperaConfigError";
  return KheperaConfigError(KheperaConfigField::protocol, -7, "none");
}

TEST(KheperaConfig, RejectsBadValuesNamingTheField) {
  using F = KheperaConfigField;
  const auto expect_field = [](const KheperaConfig& config, F field, std::int32_t index) {
    const KheperaConfigError error = config_error_of(config);
    EXPECT_EQ(error.field(), field) << error.what();
    EXPECT_EQ(error.index(), index) << error.what();
  };
  EXPECT_NO_THROW(Khepera{KheperaConfig{}});
  KheperaConfig c;
  c.body.radius = 0.0;
  expect_field(c, F::body, -1);
  c = {};
  c.body.wheel_base = std::nan("");
  expect_field(c, F::body, -1);
  c = {};
  c.body.sensors[5].y = -2.7;
  expect_field(c, F::sensors, 5);
  c = {};
  c.sensors.response_c = 0.5;  // < x0^2 = 0.81: F has a pole
  expect_field(c, F::sensor_model, -1);
  c = {};
  c.sensors.side_ray_deg = 90.0;
  expect_field(c, F::sensor_model, -1);
  c = {};
  c.sensors.noise_sd = -1.0;
  expect_field(c, F::sensor_model, -1);
  c = {};
  c.sensors.noise_fraction = -0.01;
  expect_field(c, F::sensor_model, -1);
  c = {};
  c.sensors.detection_threshold = std::numeric_limits<double>::quiet_NaN();
  expect_field(c, F::sensor_model, -1);
  c = {};
  c.motion.wheel_noise = 1.0;
  expect_field(c, F::motion, -1);
  c = {};
  c.motion.collision_substeps = 0;
  expect_field(c, F::motion, -1);
  c = {};
  c.rewards.collision = -std::numeric_limits<double>::infinity();
  expect_field(c, F::rewards, -1);
  c = {};
  c.arena.max = {0.0, 100.0};
  expect_field(c, F::arena_box, -1);
  c = {};
  c.arena.obstacles = {Disc{{10.0, 10.0}, 1.0}, Segment{{3.0, 3.0}, {3.0, 3.0}}};
  expect_field(c, F::obstacles, 1);
  c.arena.obstacles = {Rectangle{{10.0, 10.0}, {5.0, 20.0}}};
  expect_field(c, F::obstacles, 0);
  c.arena.obstacles = {RotatedRectangle{{10.0, 10.0}, 0.0, 2.0, 0.0}};
  expect_field(c, F::obstacles, 0);
  c = {};
  c.arena.start = {120.0, 50.0, 0.0};
  expect_field(c, F::start, -1);
  c = {};
  c.arena.obstacles = {Disc{{52.0, 50.0}, 1.0}};  // on the start pose
  expect_field(c, F::start, -1);
  c = {};
  c.series = 0;
  expect_field(c, F::protocol, -1);
  c = {};
  c.series = 100000;
  c.steps_per_series = 100000;
  expect_field(c, F::protocol, -1);
}
}  // namespace
}  // namespace ggk::sims::khepera
