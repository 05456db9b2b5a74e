#pragma once
// Lagoudakis & Parr's inverted pendulum (sims/pendulum) on the continuous
// protocol (engine/tasks/continuous_protocol.hpp): observation (angle,
// velocity), actions left / none / right, reward 0 while balanced and -1 when
// the pendulum falls (terminal). Walks and tests start near upright (angle and
// velocity uniform in +-start_perturbation), the walks' series end at a fall
// (random episodes, as the paper's samples). Metrics: mean_return, fall_fraction
// (test episodes that fell within test_max_steps, the paper's 3000) and
// mean_steps (the balancing steps). Keys: jobs/README.md, [pendulum].

#include "engine/tasks/task_definition.hpp"

namespace ggk::engine {

TaskDefinition pendulum_task_definition();

}  // namespace ggk::engine
