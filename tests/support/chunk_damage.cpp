#include "support/chunk_damage.hpp"

#include <fstream>

namespace ggk::test_support {

ChunkPlace first_chunk(const std::filesystem::path& file, const std::string& path) {
  ChunkPlace place;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return place;
  const hid_t d = H5Dopen2(f, path.c_str(), H5P_DEFAULT);
  if (d >= 0) {
    const hid_t space = H5Dget_space(d);
    hsize_t offset[1] = {0};
    unsigned filter_mask = 0;
    if (space < 0 ||
        H5Dget_chunk_info(d, space, 0, offset, &filter_mask, &place.address, &place.size) < 0) {
      place = {};
    }
    if (space >= 0) H5Sclose(space);
    H5Dclose(d);
  }
  H5Fclose(f);
  return place;
}

void flip_byte(const std::filesystem::path& file, std::uint64_t offset) {
  std::fstream io(file, std::ios::in | std::ios::out | std::ios::binary);
  io.seekg(static_cast<std::streamoff>(offset));
  char byte = 0;
  io.get(byte);
  io.seekp(static_cast<std::streamoff>(offset));
  io.put(static_cast<char>(~byte));
}

}  // namespace ggk::test_support
