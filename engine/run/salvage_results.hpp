#pragma once
// Resuming a results file that is damaged beyond its runs: a file cut short (a
// copy stopped midway, a full disk), a byte flipped where HDF5 keeps a group's
// index or the summary, or a group whose records point past the file's end (a
// write that failed on a full disk). `--resume` cannot repair such a file in
// place (every attempt met the same damage, and a file that grew on each try
// was seen), so when the in-place resume fails for any reason but the machine
// (machine_error), rank 0 of `ggk run` starts a new file under
// "<output>.part" and copies into it every run of the damaged one that is
// complete and reads back whole (verify_run); the rest is computed again, and the
// new file takes the output's name with its first write, as a new file does
// (open_results.hpp). The damaged file is kept beside it under a new name (a hard
// link made before anything is written), so nothing it held is lost; when every
// run it marked complete was copied whole, the link is removed again (the copy
// would keep only what is computed again: a killed writer's unfinished run).
// Not thread-safe: the caller holds the output's lock.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/study.hpp"

namespace ggk::engine {

// Whether an error of an in-place resume comes from the machine (no room, a
// file size limit, permissions, a read-only file system, a quota) rather than
// from the file: then a new file would meet it too, and it is reported as is.
bool machine_error(const std::string& message);

// Links `output` under "<stem>.damaged.h5" (or "<stem>.damaged-N.h5", N < 100, the
// first free name) in its folder and returns that path. Throws UsageError naming
// both when no link can be made (a file system without hard links).
std::filesystem::path keep_damaged_aside(const std::filesystem::path& output);

// Copies into `fresh` (a new file of `study`, groups of its configurations made)
// every run of `damaged` that is complete and reads back whole, configuration by
// configuration; returns the copied runs' ids per configuration, ascending. A run
// or a configuration's run list that cannot be read is left out and counted in
// `unreadable` (runs) and `lost_lists` (configurations whose list of runs could
// not be read: all their runs are computed again).
// `listed`: the run groups the readable lists hold (complete or not); every one
// of them copied means nothing of the damaged file is lost.
struct SalvageCount {
  std::int64_t copied = 0, unreadable = 0, lost_lists = 0, listed = 0;
};
std::vector<std::vector<std::int32_t>> copy_readable_runs(const Hdf5File& damaged, Hdf5File& fresh,
                                                          const Study& study, SalvageCount& count);

}  // namespace ggk::engine
