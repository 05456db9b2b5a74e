#include "sims/arm/arm_geometry.hpp"

#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "sims/arm/arm.hpp"
#include "sims/arm/collision.hpp"
#include "sims/arm/kinematics.hpp"

namespace ggk::sims::arm {
namespace {

TEST(ArmGeometry, RejectsBadValues) {
  const auto field_of = [](const ArmGeometry& geometry) {
    try {
      check_geometry(geometry);
    } catch (const ArmConfigError& error) {
      return std::make_pair(error.field(), error.index());
    }
    ADD_FAILURE() << "expected an ArmConfigError";
    return std::make_pair(ArmConfigField::base, -2);
  };
  ArmGeometry good;
  good.obstacles = {Disc{{3.0, 0.0}, 0.5}, Rectangle{{-1.0, -1.0}, {1.0, -0.5}}};
  EXPECT_NO_THROW(check_geometry(good));

  ArmGeometry bad = good;
  bad.link2_length = 0.0;
  EXPECT_EQ(field_of(bad), std::make_pair(ArmConfigField::links, -1));
  bad = good;
  bad.base.y = std::nan("");
  EXPECT_EQ(field_of(bad), std::make_pair(ArmConfigField::base, -1));
  bad = good;
  bad.obstacles[1] = Rectangle{{-1.0, -1.0}, {1.0, -1.5}};
  EXPECT_EQ(field_of(bad), std::make_pair(ArmConfigField::obstacles, 1));
  bad = good;
  bad.obstacles[0] = Disc{{3.0, 0.0}, -0.5};
  EXPECT_EQ(field_of(bad), std::make_pair(ArmConfigField::obstacles, 0));
  bad = good;
  bad.object.radius = 0.0;
  EXPECT_EQ(field_of(bad), std::make_pair(ArmConfigField::object, -1));
}
}  // namespace
}  // namespace ggk::sims::arm
