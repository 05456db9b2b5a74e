#include "sims/khepera/khepera_config.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <variant>

#include "sims/khepera/khepera_config_error.hpp"

namespace ggk::sims::khepera {
namespace {

bool finite(Point2 p) {
  return std::isfinite(p.x) && std::isfinite(p.y);
}

void require(bool condition, KheperaConfigField field, std::int32_t index,
             const std::string& message) {
  if (!condition) throw KheperaConfigError(field, index, "khepera: " + message);
}

void check_obstacle(const Shape& shape, std::int32_t index) {
  const std::string where = "obstacle " + std::to_string(index) + ": ";
  const auto field = KheperaConfigField::obstacles;
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Segment>) {
          require(finite(s.a) && finite(s.b), field, index, where + "segment ends must be finite");
          require(s.a != s.b, field, index, where + "segment ends must differ");
        } else if constexpr (std::is_same_v<T, Rectangle>) {
          require(finite(s.min) && finite(s.max), field, index,
                  where + "rectangle corners must be finite");
          require(s.min.x < s.max.x && s.min.y < s.max.y, field, index,
                  where + "rectangle min must be below max in x and y");
        } else if constexpr (std::is_same_v<T, RotatedRectangle>) {
          require(finite(s.center) && std::isfinite(s.angle_deg), field, index,
                  where + "rotated rectangle centre and angle must be finite");
          require(
              std::isfinite(s.width) && std::isfinite(s.height) && s.width > 0.0 && s.height > 0.0,
              field, index, where + "rotated rectangle width and height must be > 0");
        } else {
          require(finite(s.center), field, index, where + "disc centre must be finite");
          require(std::isfinite(s.radius) && s.radius > 0.0, field, index,
                  where + "disc radius must be > 0");
        }
      },
      shape);
}

}  // namespace

void check_config(const KheperaConfig& config) {
  using F = KheperaConfigField;
  const RobotBody& body = config.body;
  require(std::isfinite(body.radius) && body.radius > 0.0, F::body, -1, "body radius must be > 0");
  require(std::isfinite(body.wheel_base) && body.wheel_base > 0.0, F::body, -1,
          "wheel base must be > 0");
  for (std::int32_t i = 0; i < kNumSensors; ++i) {
    const IrSensor& sensor = body.sensors[static_cast<std::size_t>(i)];
    const std::string where = "sensor " + std::to_string(i) + ": ";
    require(std::isfinite(sensor.x) && std::isfinite(sensor.y) && std::isfinite(sensor.heading_deg),
            F::sensors, i, where + "position and heading must be finite");
    require(std::hypot(sensor.x, sensor.y) < body.radius, F::sensors, i,
            where + "must be mounted strictly inside the body disc");
  }

  const SensorModel& model = config.sensors;
  require(std::isfinite(model.range) && model.range > 0.0, F::sensor_model, -1,
          "sensor range must be > 0");
  require(model.side_ray_deg >= 0.0 && model.side_ray_deg < 90.0, F::sensor_model, -1,
          "side ray angle must lie in [0, 90) degrees");
  require(std::isfinite(model.response_m) && model.response_m > 0.0, F::sensor_model, -1,
          "response m must be > 0");
  require(std::isfinite(model.response_x0) && std::isfinite(model.response_c) &&
              model.response_c > model.response_x0 * model.response_x0,
          F::sensor_model, -1, "response c must exceed x0^2 (F would have a pole)");
  require(std::isfinite(model.noise_sd) && model.noise_sd >= 0.0, F::sensor_model, -1,
          "sensor noise sd must be >= 0");
  require(std::isfinite(model.noise_fraction) && model.noise_fraction >= 0.0, F::sensor_model, -1,
          "sensor noise fraction must be >= 0");
  require(std::isfinite(model.detection_threshold) && model.detection_threshold >= 0.0,
          F::sensor_model, -1, "detection threshold must be >= 0");
  require(std::isfinite(model.max_reading) && model.max_reading > 0.0, F::sensor_model, -1,
          "max reading must be > 0");

  const MotionModel& motion = config.motion;
  require(std::isfinite(motion.step_cm) && motion.step_cm > 0.0, F::motion, -1,
          "step length must be > 0");
  require(motion.turn_deg > 0.0 && motion.turn_deg < 180.0, F::motion, -1,
          "turn angle must lie in (0, 180) degrees");
  require(motion.wheel_noise >= 0.0 && motion.wheel_noise < 1.0, F::motion, -1,
          "wheel noise must lie in [0, 1)");
  require(motion.collision_substeps >= 1 && motion.collision_substeps <= 1000, F::motion, -1,
          "collision sub-steps must lie in [1, 1000]");

  require(std::isfinite(config.rewards.forward) && std::isfinite(config.rewards.collision),
          F::rewards, -1, "rewards must be finite");

  const Arena& arena = config.arena;
  require(finite(arena.min) && finite(arena.max), F::arena_box, -1,
          "arena box corners must be finite");
  require(arena.min.x < arena.max.x && arena.min.y < arena.max.y, F::arena_box, -1,
          "arena box min must be below max in x and y");
  for (std::size_t i = 0; i < arena.obstacles.size(); ++i)
    check_obstacle(arena.obstacles[i], static_cast<std::int32_t>(i));
  const Pose& start = arena.start;
  require(std::isfinite(start.x) && std::isfinite(start.y) && std::isfinite(start.heading),
          F::start, -1, "start pose must be finite");
  require(start.x >= arena.min.x && start.x <= arena.max.x && start.y >= arena.min.y &&
              start.y <= arena.max.y,
          F::start, -1, "start pose must lie inside the arena box");

  constexpr std::int64_t kMaxInt32 = std::numeric_limits<std::int32_t>::max();
  require(config.series >= 1 && config.steps_per_series >= 1 && config.test_max_steps >= 1 &&
              config.test_episodes >= 1,
          F::protocol, -1, "series, steps per series, test steps and test episodes must be >= 1");
  require(std::int64_t{config.series} * config.steps_per_series <= kMaxInt32, F::protocol, -1,
          "series x steps per series must be at most 2147483647");
}

}  // namespace ggk::sims::khepera
