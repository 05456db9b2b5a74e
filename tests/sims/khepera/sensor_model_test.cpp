#include "sims/khepera/sensor_model.hpp"

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

#include "sims/khepera/khepera.hpp"

namespace ggk::sims::khepera {
namespace {

using kernels::RandomStream;

using namespace test_helpers;

TEST(KheperaSensorModel, ResponseFunctionMatchesTheFormula) {
  const IrResponse f{SensorModel{}};
  for (double x : {0.0, 0.3, 1.0, 2.5, 5.0, 9.99, 10.0}) EXPECT_NEAR(f(x), hand_f(x), 1e-9) << x;
  EXPECT_NEAR(f(0.0), 1061.142857142857, 1e-9);
  EXPECT_NEAR(f(10.0), 59.424, 1e-9);
  EXPECT_EQ(f(10.000001), 0.0);
  EXPECT_EQ(f(kNoHit), 0.0);
  // A flat wall faced squarely: the side rays' excess cancels exactly.
  const double d = 4.0;
  const double oblique = d / std::cos(15.0 * std::numbers::pi / 180.0);
  EXPECT_NEAR(f.reading(oblique, d, oblique), hand_f(d), 1e-9);
  // Side rays alone add; a centre ray alone is over-corrected.
  EXPECT_NEAR(f.reading(3.0, kNoHit, kNoHit), hand_f(3.0), 1e-12);
  EXPECT_LT(f.reading(kNoHit, 3.0, kNoHit), 0.0);
}

// Sensor noise (sensor_model.hpp). The paper: "at least one of the sensor values
// is always zero since the Khepera is never completely surrounded by obstacles".
TEST(KheperaSensorNoise, NothingInRangeReadsExactlyZeroUnderTheDefaultModel) {
  EXPECT_EQ(SensorModel{}.noise_model, SensorNoiseModel::proportional);
  // Default config (proportional, fraction 0.04) in an empty walled 1 m box: from
  // the centre every wall is 48 cm off, beyond every ray.
  const Khepera robot{KheperaConfig{}};
  RandomStream random(5, 0, 0);
  for (int t = 0; t < 2000; ++t) {
    for (double r : robot.sense({50.0, 50.0, 0.3 * t}, random)) ASSERT_EQ(r, 0.0);
  }
  // Facing a wall: the back sensors see nothing and read 0, the front ones never do.
  KheperaConfig config = open_config({kWallAt60});
  config.sensors.noise_fraction = 0.2;  // loud (1 + 0.2 z > 0 unless z < -5), still proportional
  const Khepera walled(config);
  for (int t = 0; t < 2000; ++t) {
    const Readings r = walled.sense({54.9, 50.0, 0.0}, random);
    ASSERT_EQ(r[6], 0.0);
    ASSERT_EQ(r[7], 0.0);
    ASSERT_GT(r[2], 0.0);
  }
  // Threshold model: nothing in range reads 0 unless N(0, 20) alone passes 60
  // (P = 1 - Phi(3) = 0.00135).
  KheperaConfig threshold = open_config({});
  threshold.sensors.noise_model = SensorNoiseModel::threshold;
  threshold.sensors.noise_sd = 20.0;
  threshold.sensors.detection_threshold = 60.0;
  const Khepera quiet(threshold);
  std::int64_t nonzero = 0, total = 0;
  for (int t = 0; t < 50000; ++t) {
    for (double r : quiet.sense({50.0, 50.0, 0.0}, random)) {
      nonzero += r != 0.0;
      ++total;
      if (r != 0.0) {
        ASSERT_GE(r, 60.0);
      }
    }
  }
  EXPECT_NEAR(static_cast<double>(nonzero) / static_cast<double>(total), 0.00135, 0.0003);
}

// Mean and sd of n draws of sensor `sensor` at `pose`.
std::pair<double, double> reading_moments(const Khepera& robot, const Pose& pose,
                                          std::int32_t sensor, std::int32_t n,
                                          RandomStream& random) {
  double sum = 0.0, squares = 0.0;
  for (std::int32_t t = 0; t < n; ++t) {
    const double r = robot.sense(pose, random)[static_cast<std::size_t>(sensor)];
    sum += r;
    squares += r * r;
  }
  const double mean = sum / n;
  return {mean, std::sqrt((squares - n * mean * mean) / (n - 1))};
}

TEST(KheperaSensorNoise, NoiseStatisticsMatchTheModel) {
  const std::int32_t n = 40000;
  RandomStream random(11, 0, 0);
  // s2 faces the wall 3.5 cm off: F = 7428 / 25.55 = 290.7 (far from 0 and 1023,
  // so clamping and the threshold do not touch the moments).
  const Pose pose{54.9, 50.0, 0.0};
  const double f = 7428.0 / 25.55;
  {
    KheperaConfig config = open_config({kWallAt60});
    config.sensors.noise_fraction = 0.04;  // sd 0.04 F = 11.6
    const auto [mean, sd] = reading_moments(Khepera(config), pose, 2, n, random);
    EXPECT_NEAR(mean, f, 4.0 * 0.04 * f / std::sqrt(n));
    EXPECT_NEAR(sd / (0.04 * f), 1.0, 0.02);
  }
  {
    // s2 at a wall 1 cm off: F = 758, sd 0.04 F = 30.3: the sd scales with F.
    KheperaConfig config = open_config({kWallAt60});
    config.sensors.noise_fraction = 0.04;
    const double near = 7428.0 / 9.8;
    const auto [mean, sd] = reading_moments(Khepera(config), {57.4, 50.0, 0.0}, 2, n, random);
    EXPECT_NEAR(mean, near, 4.0 * 0.04 * near / std::sqrt(n));
    EXPECT_NEAR(sd / (0.04 * near), 1.0, 0.02);
  }
  for (SensorNoiseModel model : {SensorNoiseModel::additive, SensorNoiseModel::threshold}) {
    KheperaConfig config = open_config({kWallAt60});
    config.sensors.noise_model = model;
    config.sensors.noise_sd = 20.0;
    const auto [mean, sd] = reading_moments(Khepera(config), pose, 2, n, random);
    EXPECT_NEAR(mean, f, 4.0 * 20.0 / std::sqrt(n)) << to_string(model);
    EXPECT_NEAR(sd / 20.0, 1.0, 0.02) << to_string(model);
  }
}

TEST(KheperaSensorNoise, EachSensorTakesOneNormalInOrder) {
  // sense() = noisy_reading(model, noiseless, z) with z the stream's normals in
  // sensor order, one per sensor whatever it sees; by hand for one model each.
  for (SensorNoiseModel model :
       {SensorNoiseModel::proportional, SensorNoiseModel::threshold, SensorNoiseModel::additive}) {
    KheperaConfig config = open_config({kWallAt60});
    config.sensors.noise_model = model;
    config.sensors.noise_fraction = 0.1;
    config.sensors.noise_sd = 30.0;
    config.sensors.detection_threshold = 25.0;
    const Khepera robot(config);
    const Pose pose{54.9, 50.0, 0.2};
    const Readings clean = robot.sense_noiseless(pose);
    RandomStream random(23, 1, 2), replay(23, 1, 2);
    for (int t = 0; t < 50; ++t) {
      const Readings r = robot.sense(pose, random);
      for (std::size_t i = 0; i < r.size(); ++i) {
        const double z = replay.normal();
        const double by_hand = model == SensorNoiseModel::proportional
                                   ? std::clamp(clean[i] * (1.0 + 0.1 * z), 0.0, 1023.0)
                               : model == SensorNoiseModel::additive
                                   ? std::clamp(clean[i] + 30.0 * z, 0.0, 1023.0)
                               : clean[i] + 30.0 * z < 25.0 ? 0.0
                                                            : std::min(clean[i] + 30.0 * z, 1023.0);
        ASSERT_EQ(r[i], by_hand) << to_string(model) << " sensor " << i;
      }
    }
  }
}

TEST(KheperaSensorNoise, NoiseOffGivesTheHandComputedReadings) {
  // Every model at noise level 0: sense() equals the noiseless readings at the
  // hand-computed poses (F(1) = 7428 / 9.8, F(3.5) = 7428 / 25.55) and draws nothing.
  for (SensorNoiseModel model :
       {SensorNoiseModel::proportional, SensorNoiseModel::threshold, SensorNoiseModel::additive}) {
    KheperaConfig config = open_config({kWallAt60});
    config.sensors.noise_model = model;
    config.sensors.detection_threshold = 0.0;
    const Khepera robot(config);
    RandomStream random(2, 0, 0), untouched(2, 0, 0);
    EXPECT_NEAR(robot.sense({57.4, 50.0, 0.0}, random)[2], 7428.0 / 9.8, 1e-9);
    EXPECT_NEAR(robot.sense({54.9, 50.0, 0.0}, random)[2], 7428.0 / 25.55, 1e-9);
    for (const Pose& pose : {Pose{57.4, 50.0, 0.0}, Pose{54.9, 50.0, 0.0}, Pose{50.0, 45.0, 1.0}}) {
      EXPECT_EQ(robot.sense(pose, random), robot.sense_noiseless(pose)) << to_string(model);
    }
    EXPECT_EQ(random.normal(), untouched.normal()) << "no normal was drawn";
  }
}
}  // namespace
}  // namespace ggk::sims::khepera
