#include "sims/khepera/world.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <type_traits>

#include "sims/khepera/pose.hpp"

namespace ggk::sims::khepera {
namespace {

// Grid cells per side of the reach: finer cells give shorter candidate lists
// (each cell lists what lies within reach + half its diagonal of its centre).
constexpr double kCellsPerReach = 4.0;
constexpr std::int32_t kMaxCellsPerAxis = 1024;

double distance_to_segment(Point2 point, Point2 a, Point2 d, double inverse_length_squared) {
  const Point2 w = point - a;
  const double t = std::clamp(dot(w, d) * inverse_length_squared, 0.0, 1.0);
  return norm(w - t * d);
}

}  // namespace

World::World(const Arena& arena, double reach) : min_(arena.min), max_(arena.max), reach_(reach) {
  assert(reach > 0.0 && min_.x < max_.x && min_.y < max_.y);
  if (arena.walled) {
    const Point2 corners[4] = {min_, {max_.x, min_.y}, max_, {min_.x, max_.y}};
    for (int i = 0; i < 4; ++i) add_shape(Segment{corners[i], corners[(i + 1) % 4]});
  }
  for (const Shape& shape : arena.obstacles) add_shape(shape);
  build_grid();
}

void World::add_shape(const Shape& shape) {
  const auto add_polygon = [this](const Point2(&corners)[4]) {
    for (int i = 0; i < 4; ++i) {
      const Point2 a = corners[i];
      const Point2 d = corners[(i + 1) % 4] - a;
      segments_.push_back({a, d, 1.0 / dot(d, d)});
    }
  };
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Segment>) {
          const Point2 d = s.b - s.a;
          segments_.push_back({s.a, d, 1.0 / dot(d, d)});
        } else if constexpr (std::is_same_v<T, Rectangle>) {
          const Point2 corners[4] = {s.min, {s.max.x, s.min.y}, s.max, {s.min.x, s.max.y}};
          add_polygon(corners);
          boxes_.push_back({0.5 * (s.min + s.max),
                            {1.0, 0.0},
                            0.5 * (s.max.x - s.min.x),
                            0.5 * (s.max.y - s.min.y)});
        } else if constexpr (std::is_same_v<T, RotatedRectangle>) {
          const double angle = degrees_to_radians(s.angle_deg);
          const Point2 axis{std::cos(angle), std::sin(angle)};
          const Point2 across{-axis.y, axis.x};
          const Point2 u = 0.5 * s.width * axis;
          const Point2 v = 0.5 * s.height * across;
          const Point2 corners[4] = {s.center - u - v, s.center + u - v, s.center + u + v,
                                     s.center - u + v};
          add_polygon(corners);
          boxes_.push_back({s.center, axis, 0.5 * s.width, 0.5 * s.height});
        } else {
          discs_.push_back(s);
        }
      },
      shape);
}

void World::build_grid() {
  const Point2 size = max_ - min_;
  cell_size_ =
      std::max({reach_ / kCellsPerReach, size.x / kMaxCellsPerAxis, size.y / kMaxCellsPerAxis});
  cells_x_ = std::max<std::int32_t>(1, static_cast<std::int32_t>(std::ceil(size.x / cell_size_)));
  cells_y_ = std::max<std::int32_t>(1, static_cast<std::int32_t>(std::ceil(size.y / cell_size_)));
  cells_x_ = std::min(cells_x_, kMaxCellsPerAxis);
  cells_y_ = std::min(cells_y_, kMaxCellsPerAxis);

  // A primitive can matter to a query from a point p of the cell with extent <=
  // reach only if it lies within reach of p, hence within reach + half the cell's
  // diagonal of the cell's centre.
  const double limit = reach_ + 0.5 * std::sqrt(2.0) * cell_size_;
  const auto segment_near = [&](Point2 q, const SegmentPrimitive& s) {
    return distance_to_segment(q, s.a, s.d, s.inverse_length_squared) <= limit;
  };
  const auto disc_near = [&](Point2 q, const Disc& d) {
    return norm(q - d.center) - d.radius <= limit;
  };
  const auto box_near = [&](Point2 q, const BoxPrimitive& b) {
    const Point2 w = q - b.center;
    const double du = std::max(std::abs(dot(w, b.axis)) - b.half_width, 0.0);
    const double dv = std::max(std::abs(cross(b.axis, w)) - b.half_height, 0.0);
    return std::hypot(du, dv) <= limit;
  };

  const auto num_cells = static_cast<std::size_t>(cells_x_) * static_cast<std::size_t>(cells_y_);
  cells_.reserve(num_cells + 1);
  const auto append = [this](auto&& near_list, auto&& is_near) {
    for (std::size_t i = 0; i < near_list.size(); ++i)
      if (is_near(near_list[i])) candidates_.push_back(static_cast<std::int32_t>(i));
  };
  for (std::int32_t iy = 0; iy < cells_y_; ++iy) {
    for (std::int32_t ix = 0; ix < cells_x_; ++ix) {
      const Point2 q{min_.x + (ix + 0.5) * cell_size_, min_.y + (iy + 0.5) * cell_size_};
      CellCandidates cell;
      cell.begin[0] = static_cast<std::int32_t>(candidates_.size());
      append(segments_, [&](const SegmentPrimitive& s) { return segment_near(q, s); });
      cell.begin[1] = static_cast<std::int32_t>(candidates_.size());
      append(discs_, [&](const Disc& d) { return disc_near(q, d); });
      cell.begin[2] = static_cast<std::int32_t>(candidates_.size());
      append(boxes_, [&](const BoxPrimitive& b) { return box_near(q, b); });
      cell.begin[3] = static_cast<std::int32_t>(candidates_.size());
      cells_.push_back(cell);
    }
  }
  // The last entry lists everything: queries from outside the box or beyond reach.
  CellCandidates all;
  all.begin[0] = static_cast<std::int32_t>(candidates_.size());
  append(segments_, [](const SegmentPrimitive&) { return true; });
  all.begin[1] = static_cast<std::int32_t>(candidates_.size());
  append(discs_, [](const Disc&) { return true; });
  all.begin[2] = static_cast<std::int32_t>(candidates_.size());
  append(boxes_, [](const BoxPrimitive&) { return true; });
  all.begin[3] = static_cast<std::int32_t>(candidates_.size());
  cells_.push_back(all);
}

const World::CellCandidates& World::cell_of(Point2 point, double extent) const {
  // Negated comparisons also send NaN coordinates to the exhaustive list.
  if (!(extent <= reach_) || !(point.x >= min_.x && point.x <= max_.x) ||
      !(point.y >= min_.y && point.y <= max_.y))
    return cells_.back();
  const auto ix =
      std::min(static_cast<std::int32_t>((point.x - min_.x) / cell_size_), cells_x_ - 1);
  const auto iy =
      std::min(static_cast<std::int32_t>((point.y - min_.y) / cell_size_), cells_y_ - 1);
  return cells_[static_cast<std::size_t>(iy) * static_cast<std::size_t>(cells_x_) +
                static_cast<std::size_t>(ix)];
}

double World::ray_distance(Point2 origin, Point2 direction, double max_range) const {
  double distance = kNoHit;
  ray_distances(origin, {&direction, 1}, max_range, {&distance, 1});
  return distance;
}

void World::ray_distances(Point2 origin, std::span<const Point2> directions, double max_range,
                          std::span<double> distances) const {
  assert(directions.size() == distances.size());
  const CellCandidates& cell = cell_of(origin, max_range);
  const std::int32_t* index = candidates_.data();
  const std::size_t rays = directions.size();
  for (std::size_t r = 0; r < rays; ++r) distances[r] = kNoHit;
  // Segment a + s d meets the ray origin + t u where t u - s d = a - origin =: w;
  // crossing with d and with u gives t = (w x d) / (u x d), s = (w x u) / (u x d).
  // The tests t >= 0 and 0 <= s <= 1 run on the numerators, with the signs made
  // positive, so that only a hit pays a division. A ray parallel to a segment
  // (u x d == 0) never counts as meeting it: the segments joined to its ends catch
  // a ray that runs along it.
  for (std::int32_t k = cell.begin[0]; k < cell.begin[1]; ++k) {
    const SegmentPrimitive& s = segments_[index[k]];
    const Point2 w = s.a - origin;
    const double w_cross_d = cross(w, s.d);
    for (std::size_t r = 0; r < rays; ++r) {
      double denominator = cross(directions[r], s.d);
      double t_numerator = w_cross_d;
      double s_numerator = cross(w, directions[r]);
      if (denominator < 0.0) {
        denominator = -denominator;
        t_numerator = -t_numerator;
        s_numerator = -s_numerator;
      }
      if (!(denominator > 0.0) || t_numerator < 0.0 || s_numerator < 0.0 ||
          s_numerator > denominator)
        continue;
      const double t = t_numerator / denominator;
      if (t < distances[r]) distances[r] = t;
    }
  }
  // |origin + t u - c|^2 = r^2: t^2 + 2 b t + (|w|^2 - r^2) = 0 with w = origin - c,
  // b = w . u; the nearer root in front of the origin (the far one from inside).
  for (std::int32_t k = cell.begin[1]; k < cell.begin[2]; ++k) {
    const Disc& disc = discs_[index[k]];
    const Point2 w = origin - disc.center;
    const double excess = dot(w, w) - disc.radius * disc.radius;
    for (std::size_t r = 0; r < rays; ++r) {
      const double b = dot(w, directions[r]);
      const double discriminant = b * b - excess;
      if (discriminant < 0.0) continue;
      const double root = std::sqrt(discriminant);
      double t = -b - root;
      if (t < 0.0) t = -b + root;
      if (t >= 0.0 && t < distances[r]) distances[r] = t;
    }
  }
  for (std::size_t r = 0; r < rays; ++r)
    if (!(distances[r] <= max_range)) distances[r] = kNoHit;
}

bool World::disc_overlaps(Point2 center, double radius) const {
  const CellCandidates& cell = cell_of(center, radius);
  const std::int32_t* index = candidates_.data();
  const double radius_squared = radius * radius;
  for (std::int32_t k = cell.begin[0]; k < cell.begin[1]; ++k) {
    const SegmentPrimitive& s = segments_[index[k]];
    const Point2 w = center - s.a;
    const double t = std::clamp(dot(w, s.d) * s.inverse_length_squared, 0.0, 1.0);
    const Point2 gap = w - t * s.d;
    if (dot(gap, gap) < radius_squared) return true;
  }
  for (std::int32_t k = cell.begin[1]; k < cell.begin[2]; ++k) {
    const Disc& disc = discs_[index[k]];
    const Point2 gap = center - disc.center;
    const double touching = radius + disc.radius;
    if (dot(gap, gap) < touching * touching) return true;
  }
  // Near a box's edges the segments above decide; only a centre deep inside is left.
  for (std::int32_t k = cell.begin[2]; k < cell.begin[3]; ++k) {
    const BoxPrimitive& box = boxes_[index[k]];
    const Point2 w = center - box.center;
    if (std::abs(dot(w, box.axis)) <= box.half_width &&
        std::abs(cross(box.axis, w)) <= box.half_height)
      return true;
  }
  return false;
}

}  // namespace ggk::sims::khepera
