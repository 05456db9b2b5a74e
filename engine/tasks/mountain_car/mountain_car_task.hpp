#pragma once
// The mountain car (sims/mountain_car: Gymnasium MountainCar-v0) on the
// continuous protocol (engine/tasks/continuous_protocol.hpp): observation
// (position, velocity), actions push left / none / push right, reward -1 a
// step, the goal terminal. Walks start uniformly over the state box (or at
// Gymnasium's reset, walk_start = "reset"); tests at Gymnasium's reset, drawn
// from the run's evaluation stream. Metrics: mean_return, success_rate (the
// share of test episodes that reach the goal within test_max_steps) and
// mean_steps. Keys: jobs/README.md, [mountain_car].

#include "engine/tasks/task_definition.hpp"

namespace ggk::engine {

TaskDefinition mountain_car_task_definition();

}  // namespace ggk::engine
