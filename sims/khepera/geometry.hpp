#pragma once
// Plane geometry of the Khepera arena: the shared shapes (sims/geometry.hpp), all
// four of which an arena may hold; lengths in centimetres.

#include <limits>
#include <variant>

#include "sims/geometry.hpp"

namespace ggk::sims::khepera {

// The distance a ray reports when it meets nothing within range.
inline constexpr double kNoHit = std::numeric_limits<double>::infinity();

using sims::Disc;
using sims::Point2;
using sims::Rectangle;
using sims::RotatedRectangle;
using sims::Segment;

using Shape = std::variant<Segment, Rectangle, RotatedRectangle, Disc>;

}  // namespace ggk::sims::khepera
