#pragma once
// The arena compiled for fast queries: every wall and obstacle as primitives
// (segments for walls and box edges, discs, and solid boxes for "inside a
// rectangle"), with a uniform grid over the arena's box that lists, per cell,
// the primitives within `reach` of any point of the cell.
//
// Queries:
// - ray_distance: how far a ray travels before it meets a surface (a segment, a
//   box edge or a disc's circle), or kNoHit beyond max_range. Surfaces are opaque:
//   nothing behind the first one counts.
// - disc_overlaps: whether an open disc (the robot's body) overlaps a wall or
//   obstacle: a segment, disc or box nearer to its centre than its radius, or its
//   centre inside a box. Touching (distance == radius) is not an overlap.
// Both are exact; the grid only skips primitives that cannot matter. It serves
// queries whose extent (max_range, radius) is at most `reach`, from points in the
// arena's box; others fall back to testing every primitive (still exact).
//
// Thread-safety: immutable after construction; share freely.

#include <cstdint>
#include <span>
#include <vector>

#include "sims/khepera/arena.hpp"
#include "sims/khepera/geometry.hpp"

namespace ggk::sims::khepera {

class World {
 public:
  // `arena` must be valid (check_arena); reach > 0 (cm).
  World(const Arena& arena, double reach);

  // Distance from `origin` along the unit vector `direction` to the first surface
  // met at distance in [0, max_range], or kNoHit. A ray starting inside a disc or
  // box meets its boundary on the way out.
  double ray_distance(Point2 origin, Point2 direction, double max_range) const;

  // ray_distance of several rays from one origin (a sensor's fan), one pass over
  // the candidates: distances[k] for directions[k]; the spans have equal sizes.
  void ray_distances(Point2 origin, std::span<const Point2> directions, double max_range,
                     std::span<double> distances) const;

  // Whether the open disc of `radius` around `center` overlaps any wall or obstacle.
  bool disc_overlaps(Point2 center, double radius) const;

  Point2 min() const { return min_; }
  Point2 max() const { return max_; }
  double reach() const { return reach_; }
  std::int32_t num_segments() const { return static_cast<std::int32_t>(segments_.size()); }
  std::int32_t num_discs() const { return static_cast<std::int32_t>(discs_.size()); }
  std::int32_t num_boxes() const { return static_cast<std::int32_t>(boxes_.size()); }

 private:
  struct SegmentPrimitive {
    Point2 a;
    Point2 d;  // b - a
    double inverse_length_squared;
  };
  struct BoxPrimitive {
    Point2 center;
    Point2 axis;  // unit vector along the width
    double half_width;
    double half_height;
  };
  // Index ranges into candidates_ for one cell: [begin[k], begin[k + 1]) lists
  // segments (k = 0), discs (k = 1) and boxes (k = 2).
  struct CellCandidates {
    std::int32_t begin[4];
  };

  void add_shape(const Shape& shape);
  void build_grid();
  const CellCandidates& cell_of(Point2 point, double extent) const;

  Point2 min_;
  Point2 max_;
  double reach_;
  std::vector<SegmentPrimitive> segments_;
  std::vector<Disc> discs_;
  std::vector<BoxPrimitive> boxes_;

  double cell_size_ = 1.0;
  std::int32_t cells_x_ = 0;
  std::int32_t cells_y_ = 0;
  std::vector<CellCandidates> cells_;  // cells_x_ * cells_y_ row-major by y, then one for "all"
  std::vector<std::int32_t> candidates_;
};

}  // namespace ggk::sims::khepera
