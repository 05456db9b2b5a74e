#pragma once
// Plane geometry shared by the simulators: points, their vector operations, and
// the shapes job files name (segments, boxes, rotated boxes, discs). Plain data;
// each simulator documents its units and which shapes it accepts (sims/arm: boxes
// and discs; sims/khepera: all four). Angles in degrees where a person writes them
// (RotatedRectangle::angle_deg), in radians inside computations.

#include <cmath>

namespace ggk::sims {

struct Point2 {
  double x = 0.0;
  double y = 0.0;
  friend bool operator==(const Point2&, const Point2&) = default;
};

inline Point2 operator+(Point2 a, Point2 b) {
  return {a.x + b.x, a.y + b.y};
}
inline Point2 operator-(Point2 a, Point2 b) {
  return {a.x - b.x, a.y - b.y};
}
inline Point2 operator*(double s, Point2 a) {
  return {s * a.x, s * a.y};
}
inline double dot(Point2 a, Point2 b) {
  return a.x * b.x + a.y * b.y;
}
// z component of the 3-D cross product: > 0 when b is counter-clockwise of a.
inline double cross(Point2 a, Point2 b) {
  return a.x * b.y - a.y * b.x;
}
inline double norm(Point2 a) {
  return std::hypot(a.x, a.y);
}
// `a` turned counter-clockwise by the angle whose cosine and sine are given.
inline Point2 rotated(Point2 a, double cos_angle, double sin_angle) {
  return {cos_angle * a.x - sin_angle * a.y, sin_angle * a.x + cos_angle * a.y};
}

// A thin wall: the closed segment [a, b], a != b. It has no inside.
struct Segment {
  Point2 a;
  Point2 b;
  friend bool operator==(const Segment&, const Segment&) = default;
};

// The closed axis-aligned box [min.x, max.x] x [min.y, max.y] (solid).
struct Rectangle {
  Point2 min;
  Point2 max;
  friend bool operator==(const Rectangle&, const Rectangle&) = default;
};

// A solid box of `width` x `height` (> 0) centred at `center`, its width axis
// turned `angle_deg` counter-clockwise from the x axis.
struct RotatedRectangle {
  Point2 center;
  double width = 1.0;
  double height = 1.0;
  double angle_deg = 0.0;
  friend bool operator==(const RotatedRectangle&, const RotatedRectangle&) = default;
};

// The closed disc of `radius` > 0 around `center` (solid).
struct Disc {
  Point2 center;
  double radius = 1.0;
  friend bool operator==(const Disc&, const Disc&) = default;
};

}  // namespace ggk::sims
