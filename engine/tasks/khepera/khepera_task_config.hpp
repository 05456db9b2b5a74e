#pragma once
// Parameters of the Khepera task: the simulator's (sims/khepera) and the
// continuous protocol's (the walks, the test and the self-organising map that
// discretises the readings into graph nodes). The readings are not scaled: the
// paper works in raw IR readings (width 1000 in reading units), so the task has
// no [khepera.scale] table and protocol.scale is empty.

#include "engine/tasks/continuous_protocol.hpp"
#include "sims/khepera/khepera_config.hpp"

namespace ggk::engine {

struct KheperaTaskConfig {
  sims::khepera::KheperaConfig simulator;
  // series, steps_per_series, test_max_steps and test_episodes as the
  // simulator's; som: paper sec. 4.2, 24 x 29 = 696 units (5 sqrt(n) for
  // n = 20,000 samples).
  ContinuousProtocol protocol;
};

}  // namespace ggk::engine
