#pragma once
// A run's digest: what no HDF5 checksum covers in the format ggk writes. The
// files use HDF5's 1.8-compatible format (hdf5_file.hpp says why), whose object
// headers, group B-trees and heaps carry no checksums; only dataset chunks do
// (Fletcher32). A flipped byte there could rename a dataset or an attribute or
// change an attribute's value or a dataset's shape, and every read would still
// succeed. The digest is a 64-bit FNV-1a hash over the run group's tree, in name
// order: each object's path below the group and kind, each dataset's shape,
// each attribute's name, type, shape and value. Dataset values are left to their
// chunk checksums; wall-clock attributes (fit_seconds) and the group's own
// `complete` and `digest` marks are left out.
//
// write_run stores it as the run group's int64 attribute `digest` (the bits of
// the hash) before the run is marked complete; verify_run (and so --resume and
// merge) recomputes it and calls the run damaged when it differs. Runs written
// before the digest existed have none and are not compared. Reads metadata
// only: cheap beside reading the run. Thread-safe as Hdf5File reads are.

#include <cstdint>
#include <string>

#include "engine/hdf5/hdf5_file.hpp"

namespace ggk::engine {

inline constexpr const char* kRunDigestAttribute = "digest";

// The digest of the run group at `group` (e.g. "/maze/run_003"). Throws
// std::runtime_error when the tree does not read, holds a soft or external
// link or nests deeper than 32 groups.
std::uint64_t run_digest(const Hdf5File& file, const std::string& group);

}  // namespace ggk::engine
