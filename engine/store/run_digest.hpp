#pragma once
// A run's digest: what no HDF5 checksum covers in the format ggk writes. The
// files use HDF5's 1.8-compatible format (hdf5_file.hpp says why), whose object
// headers, group B-trees and heaps carry no checksums; only dataset chunks do
// (Fletcher32). A flipped byte there could rename a dataset or an attribute,
// change an attribute's value or a dataset's shape, or point a dataset at
// another's chunks (which then pass their own checksums: measured, 3 of 40
// random overwrites of a results file substituted a dataset's values this
// way), and every read would still succeed. The digest is a 64-bit FNV-1a hash
// over the run group's tree, in name order: each object's path below the group
// and kind, each dataset's shape and values, each attribute's name, type, shape
// and value. Wall-clock values (the fit_seconds attribute and table column) and
// the group's own `complete` and digest marks are left out, so that one job's
// runs get one digest whatever the machine.
//
// write_run stores it as the run group's int64 attribute `content_digest` (the
// bits of the hash) before the run is marked complete; verify_run (and so
// --resume and merge) recomputes it and calls the run damaged when it differs.
// Runs written before it carry the older `digest`, which covered no dataset
// values, and are checked against that; runs older still carry none. Reads the
// run's data: about what verify_run reads for the checksums. Thread-safe as
// Hdf5File reads are.

#include <cstdint>
#include <string>

#include "engine/hdf5/hdf5_file.hpp"

namespace ggk::engine {

inline constexpr const char* kRunDigestAttribute = "content_digest";
// The digest of runs written before the content digest: names, attributes and
// shapes, no dataset values.
inline constexpr const char* kMetadataDigestAttribute = "digest";

enum class DigestScope {
  kContent,   // kRunDigestAttribute's: dataset values included
  kMetadata,  // kMetadataDigestAttribute's: names, attributes, shapes
};

// The digest of the run group at `group` (e.g. "/maze/run_003"). Throws
// std::runtime_error when the tree does not read, holds a soft or external
// link or nests deeper than 32 groups.
std::uint64_t run_digest(const Hdf5File& file, const std::string& group,
                         DigestScope scope = DigestScope::kContent);

}  // namespace ggk::engine
