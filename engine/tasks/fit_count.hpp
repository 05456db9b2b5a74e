#pragma once
// Fits finished in this process, counted as each ends: what the progress display
// (run/progress.hpp) shows between the ends of runs (a run of a paper job takes
// seconds to minutes; a display that moves only when a run commits said
// "runs 0/1, 0.0 fits/s, eta --" throughout a 52 s run). The protocols
// (discrete_protocol.cpp, continuous_protocol.cpp) call count_fit_done() after
// each fit, on whatever thread computed it. Only this process's fits: an MPI
// worker sends its count to rank 0 with each heartbeat and result
// (run/mpi_runner.cpp), whose display adds them.

#include <cstdint>

namespace ggk::engine {

void count_fit_done();
std::int64_t fits_done();  // since the process started

}  // namespace ggk::engine
