#pragma once
// The Khepera I robot (paper sec. 4.2, Fig. 4(a)): a disc body on two wheels
// (differential drive) with 8 infra-red proximity sensors around its rim. Plain
// data; defaults are the real robot's (K-Team), positions in centimetres in the
// robot's frame: x forward, y to the left, origin at the body's centre (midway
// between the wheels).

#include <array>
#include <cstdint>

namespace ggk::sims::khepera {

inline constexpr std::int32_t kNumSensors = 8;

// One IR sensor: its mounting point and the direction it looks, in degrees
// counter-clockwise from the robot's forward axis.
struct IrSensor {
  double x = 0.0;
  double y = 0.0;
  double heading_deg = 0.0;
  friend bool operator==(const IrSensor&, const IrSensor&) = default;
};

// s0..s7 of DESIGN.md sec. 3: s0 looks left, s1 front-left, s2 and s3 forward,
// s4 front-right, s5 right, s6 and s7 backward. (The paper numbers them s1..s8.)
inline constexpr std::array<IrSensor, kNumSensors> kKheperaSensors = {{
    {1.0, 1.5, 90.0},
    {1.3, 1.3, 45.0},
    {1.6, 0.6, 0.0},
    {1.6, -0.6, 0.0},
    {1.3, -1.3, -45.0},
    {1.0, -1.5, -90.0},
    {-1.5, -1.0, 180.0},
    {-1.5, 1.0, 180.0},
}};

struct RobotBody {
  double radius = 2.6;      // cm, > 0; the body is this closed disc
  double wheel_base = 5.2;  // cm, > 0; distance between the wheels' contact points
  // Mounting points must lie strictly inside the body disc, so that every ray
  // starts in free space (the body never overlaps a wall or an obstacle).
  std::array<IrSensor, kNumSensors> sensors = kKheperaSensors;
  friend bool operator==(const RobotBody&, const RobotBody&) = default;
};

}  // namespace ggk::sims::khepera
