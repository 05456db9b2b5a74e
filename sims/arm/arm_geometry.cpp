#include "sims/arm/arm_geometry.hpp"

#include <cmath>
#include <string>

#include "sims/arm/arm_config_error.hpp"

namespace ggk::sims::arm {
namespace {

void check_finite(double value, ArmConfigField field, std::int32_t index, const std::string& what) {
  if (!std::isfinite(value)) {
    throw ArmConfigError(field, index, "arm geometry: " + what + " is not a finite number");
  }
}

void check_point(const Point2& point, ArmConfigField field, std::int32_t index,
                 const std::string& what) {
  check_finite(point.x, field, index, what + ".x");
  check_finite(point.y, field, index, what + ".y");
}

void check_disc(const Disc& disc, ArmConfigField field, std::int32_t index,
                const std::string& what) {
  check_point(disc.center, field, index, what + " centre");
  check_finite(disc.radius, field, index, what + " radius");
  if (disc.radius <= 0.0) {
    throw ArmConfigError(
        field, index,
        "arm geometry: " + what + " radius " + std::to_string(disc.radius) + " is not > 0");
  }
}

}  // namespace

void check_geometry(const ArmGeometry& geometry) {
  check_finite(geometry.link1_length, ArmConfigField::links, -1, "link 1 length");
  check_finite(geometry.link2_length, ArmConfigField::links, -1, "link 2 length");
  if (geometry.link1_length <= 0.0 || geometry.link2_length <= 0.0) {
    throw ArmConfigError(ArmConfigField::links, -1, "arm geometry: link lengths must be > 0");
  }
  check_point(geometry.base, ArmConfigField::base, -1, "base");
  for (std::size_t i = 0; i < geometry.obstacles.size(); ++i) {
    const auto index = static_cast<std::int32_t>(i);
    const std::string what = "obstacle " + std::to_string(i);
    if (const auto* rectangle = std::get_if<Rectangle>(&geometry.obstacles[i])) {
      check_point(rectangle->min, ArmConfigField::obstacles, index, what + " min");
      check_point(rectangle->max, ArmConfigField::obstacles, index, what + " max");
      if (rectangle->min.x > rectangle->max.x || rectangle->min.y > rectangle->max.y) {
        throw ArmConfigError(ArmConfigField::obstacles, index,
                             "arm geometry: " + what + " (rectangle) has min > max");
      }
    } else {
      check_disc(std::get<Disc>(geometry.obstacles[i]), ArmConfigField::obstacles, index,
                 what + " (disc)");
    }
  }
  check_disc(geometry.object, ArmConfigField::object, -1, "object");
}

}  // namespace ggk::sims::arm
