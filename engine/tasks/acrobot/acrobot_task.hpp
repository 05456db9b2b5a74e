#pragma once
// The acrobot (sims/acrobot: Gymnasium Acrobot-v1) on the continuous protocol
// (engine/tasks/continuous_protocol.hpp): Gymnasium's 6-D observation, torques
// -1 / 0 / +1, reward -1 a step and 0 when the tip rises above the bar
// (terminal). Walks start uniformly over the state box (or at Gymnasium's reset,
// walk_start = "reset"); tests at Gymnasium's reset (all four state variables
// uniform in +-0.1), drawn from the run's evaluation stream. Metrics:
// mean_return, success_rate (test episodes that reached the bar within
// test_max_steps, Gymnasium's 500) and mean_steps. Keys: jobs/README.md, [acrobot].

#include "engine/tasks/task_definition.hpp"

namespace ggk::engine {

TaskDefinition acrobot_task_definition();

}  // namespace ggk::engine
