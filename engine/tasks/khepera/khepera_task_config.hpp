#pragma once
// Parameters of the Khepera task: the simulator's (sims/khepera) and the
// self-organising map that discretises the readings into graph nodes.

#include "kernels/self_organizing_map.hpp"
#include "sims/khepera/khepera_config.hpp"

namespace ggk::engine {

struct KheperaTaskConfig {
  sims::khepera::KheperaConfig simulator;
  // Paper sec. 4.2: 24 x 29 = 696 units (5 sqrt(n) for n = 20,000 samples).
  kernels::SomOptions som;
  // Derive rows x cols from the samples (kernels::som_grid_for) instead of som.rows/cols.
  bool som_grid_from_samples = false;
};

}  // namespace ggk::engine
