#pragma once
// Is a results file whole? Reads every dataset and attribute back, which checks
// every checksum HDF5 keeps (Fletcher32 per chunk of every dataset; the object
// headers, B-trees and heaps of the 1.10 formats): damage to the bytes of a file
// (a bad disk, a stray write, a copy cut short) becomes an error naming what is
// damaged, never wrong numbers read in silence.
//
// `ggk verify FILE` (verify_results), and `ggk run --resume`, which checks each
// run it keeps (verify_run) and computes a damaged one again. Datasets without
// checksums are read the same way, but only damage that makes HDF5 fail is found
// in them.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include "engine/hdf5/hdf5_file.hpp"

namespace ggk::engine {

// Empty when every dataset and attribute of the run's group reads back and the
// run is whole (run_shape_problem); else what failed first (path and reason,
// cut to a line). `task`: a run location (run_store.hpp: "maze/config_002").
std::optional<std::string> verify_run(const Hdf5File& file, const std::string& task,
                                      std::int32_t run);

// Empty when the run's group has what write_run writes (run_store.hpp): the
// samples' five datasets, the graph, a fit_metrics table with the columns every
// task's has (run, sweep_point, basis, kernels, sigma, solver, lambda, status,
// of their types), and one fit group under fits/ per row of it; else what is
// missing or wrong. A run whose objects all read can still be cut (a deleted
// fits group) or replaced (other datasets): it is not complete then.
std::optional<std::string> run_shape_problem(const Hdf5File& file, const std::string& task,
                                             std::int32_t run);

// Empty when everything of the file but its runs reads back: the root's and the
// groups' attributes, the summary, any other object (the writer's /.staging
// scratch aside); else what failed first. `--resume` checks it once, after each
// run it keeps: what is damaged there cannot be computed again in place.
std::optional<std::string> verify_beyond_runs(const Hdf5File& file);

// Reads the whole file (the writer's /.staging scratch aside) and prints the
// verdict to `out`: counts of datasets and attributes read, runs complete, and
// each damaged object. Returns true when nothing is damaged. Throws UsageError
// when the file does not exist, is not HDF5 or is no ggk results file.
bool verify_results(const std::filesystem::path& path, std::ostream& out);

}  // namespace ggk::engine
