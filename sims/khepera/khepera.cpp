#include "sims/khepera/khepera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace ggk::sims::khepera {
namespace {

constexpr std::int64_t kMaxFreePoseTries = 1'000'000;

KheperaConfig checked(KheperaConfig config) {
  check_config(config);
  return config;
}

}  // namespace

Khepera::Khepera(KheperaConfig config)
    : config_(checked(std::move(config))),
      // The grid must serve ray casts (range) and body overlap tests (radius).
      world_(config_.arena, std::max(config_.sensors.range, config_.body.radius)),
      response_(config_.sensors),
      start_pose_{config_.arena.start.x, config_.arena.start.y,
                  wrap_angle(config_.arena.start.heading)} {
  const double side = degrees_to_radians(config_.sensors.side_ray_deg);
  for (std::size_t i = 0; i < sensors_.size(); ++i) {
    const IrSensor& sensor = config_.body.sensors[i];
    const double heading = degrees_to_radians(sensor.heading_deg);
    sensors_[i].mount = {sensor.x, sensor.y};
    sensors_[i].rays = {Point2{std::cos(heading + side), std::sin(heading + side)},
                        Point2{std::cos(heading), std::sin(heading)},
                        Point2{std::cos(heading - side), std::sin(heading - side)}};
  }
  for (std::int32_t action = 0; action < kNumActions; ++action)
    commands_[static_cast<std::size_t>(action)] =
        wheel_command(config_.motion, config_.body.wheel_base, action);
  if (collides(start_pose_))
    throw KheperaConfigError(KheperaConfigField::start, -1,
                             "khepera: the body overlaps a wall or an obstacle at the start pose");
}

bool Khepera::collides(const Pose& pose) const {
  return world_.disc_overlaps({pose.x, pose.y}, config_.body.radius);
}

SensorRays Khepera::sensor_rays(const Pose& pose, std::int32_t sensor) const {
  if (sensor < 0 || sensor >= kNumSensors)
    throw std::out_of_range("khepera: sensor " + std::to_string(sensor) + " is not in [0, 8)");
  const std::array<double, 3> distances =
      fan_distances({pose.x, pose.y}, std::cos(pose.heading), std::sin(pose.heading), sensor);
  return {distances[0], distances[1], distances[2]};
}

std::array<double, 3> Khepera::fan_distances(Point2 center, double cos_heading, double sin_heading,
                                             std::int32_t sensor) const {
  const SensorGeometry& geometry = sensors_[static_cast<std::size_t>(sensor)];
  const Point2 origin = center + rotated(geometry.mount, cos_heading, sin_heading);
  std::array<Point2, 3> directions;
  for (std::size_t k = 0; k < 3; ++k)
    directions[k] = rotated(geometry.rays[k], cos_heading, sin_heading);
  std::array<double, 3> distances;
  world_.ray_distances(origin, directions, config_.sensors.range, distances);
  return distances;
}

double Khepera::noiseless_reading(Point2 center, double cos_heading, double sin_heading,
                                  std::int32_t sensor) const {
  const std::array<double, 3> d = fan_distances(center, cos_heading, sin_heading, sensor);
  return response_.reading(d[0], d[1], d[2]);
}

Readings Khepera::sense_noiseless(const Pose& pose) const {
  const double c = std::cos(pose.heading);
  const double s = std::sin(pose.heading);
  const double max_reading = config_.sensors.max_reading;
  Readings readings;
  for (std::int32_t i = 0; i < kNumSensors; ++i)
    readings[static_cast<std::size_t>(i)] =
        std::clamp(noiseless_reading({pose.x, pose.y}, c, s, i), 0.0, max_reading);
  return readings;
}

Readings Khepera::sense(const Pose& pose, kernels::RandomStream& random) const {
  const double c = std::cos(pose.heading);
  const double s = std::sin(pose.heading);
  const SensorModel& model = config_.sensors;
  const bool noisy = draws_noise(model);
  Readings readings;
  for (std::int32_t i = 0; i < kNumSensors; ++i) {
    const double value = noiseless_reading({pose.x, pose.y}, c, s, i);
    // One normal per sensor whatever it sees, so the stream's position never
    // depends on the geometry.
    const double z = noisy ? random.normal() : 0.0;
    readings[static_cast<std::size_t>(i)] = noisy_reading(model, value, z);
  }
  return readings;
}

StepResult Khepera::step(const Pose& pose, std::int32_t action,
                         kernels::RandomStream& random) const {
  check_action(action);
  WheelTravel travel = commands_[static_cast<std::size_t>(action)];
  const double noise = config_.motion.wheel_noise;
  if (noise > 0.0) {
    travel.left *= random.uniform(1.0 - noise, 1.0 + noise);
    travel.right *= random.uniform(1.0 - noise, 1.0 + noise);
  }

  StepResult result;
  result.next_pose = pose;
  const std::int32_t substeps = config_.motion.collision_substeps;
  for (std::int32_t k = 1; k <= substeps; ++k) {
    // Constant wheel speeds: the first k / K of the step rolls k / K of the travel.
    const double fraction = static_cast<double>(k) / substeps;
    const Pose along =
        drive(pose, {fraction * travel.left, fraction * travel.right}, config_.body.wheel_base);
    if (collides(along)) {
      result.collided = true;
      break;
    }
    if (k == substeps) result.next_pose = along;
  }
  result.reward = result.collided      ? config_.rewards.collision
                  : action == kForward ? config_.rewards.forward
                                       : 0.0;
  result.observation = sense(result.next_pose, random);
  return result;
}

Pose Khepera::sample_free_pose(kernels::RandomStream& random) const {
  const Point2 lo = config_.arena.min;
  const Point2 hi = config_.arena.max;
  for (std::int64_t attempt = 0; attempt < kMaxFreePoseTries; ++attempt) {
    const double x = random.uniform(lo.x, hi.x);
    const double y = random.uniform(lo.y, hi.y);
    const double heading = random.uniform(-std::numbers::pi, std::numbers::pi);
    const Pose pose{x, y, heading};
    if (!collides(pose)) return pose;
  }
  throw std::runtime_error("khepera: no collision-free pose found in " +
                           std::to_string(kMaxFreePoseTries) + " random tries");
}

}  // namespace ggk::sims::khepera
