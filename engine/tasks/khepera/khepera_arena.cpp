#include "engine/tasks/khepera/khepera_arena.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <variant>

namespace ggk::engine {

namespace khepera = sims::khepera;

std::vector<NamedArray> arena_arrays(const khepera::Khepera& robot) {
  const auto& c = robot.config();
  const khepera::Arena& arena = c.arena;
  NamedArray box{"arena/box",
                 {5},
                 {arena.min.x, arena.min.y, arena.max.x, arena.max.y, arena.walled ? 1.0 : 0.0}};
  NamedArray segments{"arena/segments", {0, 4}, {}}, rectangles{"arena/rectangles", {0, 4}, {}};
  NamedArray rotated{"arena/rotated_rectangles", {0, 5}, {}}, discs{"arena/discs", {0, 3}, {}};
  for (const khepera::Shape& shape : arena.obstacles) {
    if (const auto* g = std::get_if<khepera::Segment>(&shape)) {
      segments.values.insert(segments.values.end(), {g->a.x, g->a.y, g->b.x, g->b.y});
    } else if (const auto* r = std::get_if<khepera::Rectangle>(&shape)) {
      rectangles.values.insert(rectangles.values.end(), {r->min.x, r->min.y, r->max.x, r->max.y});
    } else if (const auto* q = std::get_if<khepera::RotatedRectangle>(&shape)) {
      rotated.values.insert(rotated.values.end(),
                            {q->center.x, q->center.y, q->width, q->height, q->angle_deg});
    } else if (const auto* d = std::get_if<khepera::Disc>(&shape)) {
      discs.values.insert(discs.values.end(), {d->center.x, d->center.y, d->radius});
    }
  }
  segments.shape[0] = static_cast<std::int64_t>(segments.values.size() / 4);
  rectangles.shape[0] = static_cast<std::int64_t>(rectangles.values.size() / 4);
  rotated.shape[0] = static_cast<std::int64_t>(rotated.values.size() / 5);
  discs.shape[0] = static_cast<std::int64_t>(discs.values.size() / 3);
  const khepera::Pose start = robot.start_pose();
  NamedArray start_pose{"arena/start", {3}, {start.x, start.y, start.heading}};
  NamedArray radius{"robot/radius", {1}, {c.body.radius}};
  NamedArray sensors{"robot/sensors", {khepera::kNumSensors, 3}, {}};
  NamedArray rays{"robot/start_rays", {3 * khepera::kNumSensors, 5}, {}};
  const double range = c.sensors.range;
  const double side = khepera::degrees_to_radians(c.sensors.side_ray_deg);
  const double ch = std::cos(start.heading), sh = std::sin(start.heading);
  for (std::int32_t i = 0; i < khepera::kNumSensors; ++i) {
    const khepera::IrSensor& mount = c.body.sensors[static_cast<std::size_t>(i)];
    sensors.values.insert(sensors.values.end(), {mount.x, mount.y, mount.heading_deg});
    const double ox = start.x + ch * mount.x - sh * mount.y;
    const double oy = start.y + sh * mount.x + ch * mount.y;
    const khepera::SensorRays hit = robot.sensor_rays(start, i);
    const double heading = start.heading + khepera::degrees_to_radians(mount.heading_deg);
    const std::array<std::pair<double, double>, 3> fan = {
        {{heading + side, hit.left}, {heading, hit.centre}, {heading - side, hit.right}}};
    for (const auto& [angle, distance] : fan) {
      const bool seen = distance <= range;
      const double length = seen ? distance : range;
      rays.values.insert(rays.values.end(), {ox, oy, ox + length * std::cos(angle),
                                             oy + length * std::sin(angle), seen ? 1.0 : 0.0});
    }
  }
  const khepera::Readings clean = robot.sense_noiseless(start);
  NamedArray readings{"robot/start_readings",
                      {khepera::kNumSensors},
                      std::vector<double>(clean.begin(), clean.end())};
  return {std::move(box),   std::move(segments),   std::move(rectangles), std::move(rotated),
          std::move(discs), std::move(start_pose), std::move(radius),     std::move(sensors),
          std::move(rays),  std::move(readings)};
}

}  // namespace ggk::engine
