#pragma once
// Damage a results file the way a bad disk or a stray write does: one byte of
// a dataset's stored chunk flipped, found with H5Dget_chunk_info.

#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <string>

namespace ggk::test_support {

// Where the first stored chunk of dataset `path` lies in `file`: its byte
// offset and size (as filtered: shuffled, compressed, checksummed).
struct ChunkPlace {
  haddr_t address = HADDR_UNDEF;
  hsize_t size = 0;
};

ChunkPlace first_chunk(const std::filesystem::path& file, const std::string& path);

// Flips every bit of the byte at `offset` of `file`.
void flip_byte(const std::filesystem::path& file, std::uint64_t offset);

}  // namespace ggk::test_support
