#pragma once
// Growing a complete run by the fits of new sweep points: a study resumed with
// more values of a fit-level axis (basis, kernels, sigma, solver, lambda,
// lspi.*; engine/run/open_results.hpp) computes only the new points' fits and
// adds them to each complete run, which then holds exactly what write_run
// writes for the run computed with every point (`ggk diff`-equal).
//
// Why the old fits can be kept as they are: a fit's results depend only on its
// run and its own point (its test draws from the run's one evaluation stream,
// engine/tasks/seeds.hpp; the run's diagnostics do not depend on the sweep,
// engine/tasks/graph_protocol.hpp). What the points' order gives them, their
// index (`sweep_point`: the attribute of each fit group and the column of
// fit_metrics), is renumbered to the grown job's.
//
// The steps, each safe against a kill: the extension (the run computed again
// with only the new fits: the same samples and graph, bit for bit) is staged as
// write_run stages a run; the old fit groups are copied beside the new ones with
// their new index; fit_metrics is rewritten with every fit's row in point order
// and the digest set again; then the staged run replaces the old one
// (commit_staged_run). A kill before the replacement leaves the old run
// complete (the staging group is discarded by the next resume, which extends
// the run again); after it, the grown run.
//
// Makes HDF5 calls: call on the StoreWriter's thread only.

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/job_spec.hpp"
#include "engine/job/sweep.hpp"
#include "engine/tasks/run_record.hpp"

namespace ggk::engine {

// The indices of `points` whose fits the complete run lacks, ascending (empty:
// it holds every one). Throws std::runtime_error when it holds a fit that is
// no point of them.
std::vector<std::int32_t> lacking_points(const Hdf5File& file, const std::string& location,
                                         std::int32_t run, std::span<const SweepPoint> points);

// `extension`: the run with the fits of the points it lacks; `points`: every
// point of the grown job (their fit group names give the old fits' new index).
// Throws std::runtime_error when the stored run does not fit the job (an old fit
// that is no point of it, other fit_metrics columns), naming the run.
void extend_run(Hdf5File& file, const JobSpec& job, const RunRecord& extension,
                std::span<const SweepPoint> points);

// The same from the in-memory image of the extension (run_store.hpp: run_image;
// an extension computed on another MPI rank).
void extend_run_from_image(Hdf5File& file, const JobSpec& job, std::int32_t run,
                           std::span<const unsigned char> image,
                           std::span<const SweepPoint> points);

// One piece of a run whose fits were computed on several MPI ranks
// (run/run_pieces.hpp): the run with some of its points, computed here
// (`record`) or on another rank (run_image's bytes: bytes[offset..];
// `extension` as the record's flag would say).
struct RunPiece {
  std::shared_ptr<const RunRecord> record;
  std::shared_ptr<const std::vector<unsigned char>> bytes;
  std::size_t offset = 0;
  bool extension = false;
};

// Writes a run computed in pieces as write_run writes it whole: the first piece
// (the one that is no extension) and every other one extending it, assembled in
// memory, then committed to `file` at once (write_run_image), so that the file
// never holds a part of the run. `points`: every point of the job. Throws
// std::runtime_error when the pieces are not one first piece and its extensions
// of `run`, or when an extension does not fit (as extend_run).
void write_run_pieces(Hdf5File& file, const JobSpec& job, std::int32_t run,
                      std::span<const RunPiece> pieces, std::span<const SweepPoint> points);

}  // namespace ggk::engine
