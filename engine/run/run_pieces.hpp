#pragma once
// Finer units of work across MPI ranks: the fits of one run spread over several
// ranks when fewer runs are left than ranks to compute them (issue 38, item 2).
//
// A queue of U units handed out to R ranks one at a time ends with a round of
// U mod R units that leaves the other ranks idle (20 runs on 16 ranks: the
// second round keeps 4 of 16 busy). split_tail_runs splits each unit of that
// last round into pieces, the R ranks shared out among them: a piece is the
// run with some of its sweep points (WorkUnit::points). The first piece is a new
// run of its points, the others extend it (WorkUnit::extends), so rank 0 writes
// the run once every piece has come (store/run_extension.hpp: write_run_pieces),
// exactly as the run computed whole (a fit depends only on its run and its own
// point). Each piece computes the run's stages again (samples, SOM, graph: 14 %
// of a khepera-paper run), which costs less than the idle ranks.
//
// A piece holds whole groups of points that share a basis table (the same
// basis, kernel count and width: their solvers and fit variants share the table
// and the solvers' fixed part), dealt out to the pieces in a snake order
// (0 1 2 2 1 0 0 1 ...), which balances the ascending kernel counts.
// A unit that extends a stored run, or of one such group, is not split.

#include <cstdint>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include "engine/job/study.hpp"

namespace ggk::engine {

struct PiecedUnits {
  std::vector<WorkUnit> units;  // in queue order; a split unit's pieces side by side
  // (configuration, run) of each split unit -> its pieces' count.
  std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> pieces;
};

// The units with those of the last round over `ranks` split (none when the
// units fill their rounds, or for one rank).
PiecedUnits split_tail_runs(const Study& study, std::span<const WorkUnit> units,
                            std::int32_t ranks);

}  // namespace ggk::engine
