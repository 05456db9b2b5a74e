#pragma once
// The geometry of Fig. 4(a) stored with every Khepera run
// (results/plot_khepera_arena.py reads it): the arena, the robot and its
// sensors' rays at the start pose.

#include <vector>

#include "engine/tasks/run_record.hpp"
#include "sims/khepera/khepera.hpp"

namespace ggk::engine {

// arena/box [min x, min y, max x, max y, walled], arena/segments [n, 4] (a, b),
// arena/rectangles [n, 4] (min, max), arena/rotated_rectangles [n, 5] (centre,
// width, height, angle_deg), arena/discs [n, 3] (centre, radius), arena/start
// [x, y, heading (rad)], robot/radius, robot/sensors [8, 3] (x, y, heading_deg
// in the robot frame), robot/start_rays [24, 5] (row 3 i + k: sensor i's left,
// centre, right ray for k = 0, 1, 2: origin, end (the hit, or the range's end),
// 1 if it hit within range; the store keeps 1-D and 2-D arrays) and
// robot/start_readings [8] (noiseless).
std::vector<NamedArray> arena_arrays(const sims::khepera::Khepera& robot);

}  // namespace ggk::engine
