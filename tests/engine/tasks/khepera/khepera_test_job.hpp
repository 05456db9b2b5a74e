#pragma once
// A valid Khepera job with an inline arena (a 4 x 5 SOM, 10 walks of 50 steps,
// one obstacle of each kind): the [khepera] table's tests refer to its lines,
// the task's tests run it.

namespace ggk::engine {

inline constexpr const char* kKheperaJob = R"(name = "khepera-test"
task = "khepera"
runs = 1
seed = 7
[sweep]
kernels = [5]
sigma = [1000.0]
[khepera]
series = 10
steps_per_series = 50
test_episodes = 2
[khepera.som]
rows = 4
cols = 5
[khepera.arena]
min = [0.0, 0.0]
max = [40, 40.0]
start = { x = 10.0, y = 10.0, heading_deg = 90.0 }
[[khepera.arena.obstacles]]
kind = "rectangle"
min = [20.0, 20.0]
max = [30.0, 30.0]
[[khepera.arena.obstacles]]
kind = "disc"
center = [10.0, 30.0]
radius = 3.0
[[khepera.arena.obstacles]]
kind = "segment"
a = [40.0, 10.0]
b = [30.0, 10.0]
[[khepera.arena.obstacles]]
kind = "rotated_rectangle"
center = [5.0, 20.0]
size = [6.0, 2.0]
angle_deg = 45.0
)";

}  // namespace ggk::engine
