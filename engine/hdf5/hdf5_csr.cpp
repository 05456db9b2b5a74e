#include "engine/hdf5/hdf5_file.hpp"

#include <hdf5.h>

#include <limits>

#include "engine/hdf5/hdf5_internals.hpp"

namespace ggk::engine {

using namespace hdf5_internals;  // NOLINT: the shared helpers of this file's parts

namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- CSR

void check_csr(const fs::path& file, const std::string& path, std::int64_t rows, std::int64_t cols,
               std::span<const std::int64_t> indptr, std::span<const std::int32_t> indices,
               std::size_t value_count) {
  const auto fail = [&](const std::string& problem) {
    throw_store_error(file, path, "invalid CSR matrix: " + problem);
  };
  if (rows < 0 || cols < 0) fail("negative shape");
  if (indptr.size() != static_cast<std::size_t>(rows) + 1) {
    fail("indptr has " + std::to_string(indptr.size()) + " entries for " + std::to_string(rows) +
         " rows");
  }
  if (indices.size() != value_count) {
    fail(std::to_string(indices.size()) + " indices but " + std::to_string(value_count) +
         " values");
  }
  if (indptr.front() != 0) fail("indptr[0] is not 0");
  for (std::size_t i = 1; i < indptr.size(); ++i) {
    if (indptr[i] < indptr[i - 1]) fail("indptr decreases at row " + std::to_string(i - 1));
  }
  if (static_cast<std::uint64_t>(indptr.back()) != indices.size()) {
    fail("indptr ends at " + std::to_string(indptr.back()) + " but there are " +
         std::to_string(indices.size()) + " entries");
  }
  for (const std::int32_t column : indices) {
    if (column < 0 || column >= cols) {
      fail("column index " + std::to_string(column) + " outside [0, " + std::to_string(cols) + ")");
    }
  }
}

}  // namespace

// ---------------------------------------------------------------- CSR

void Hdf5File::write_csr(std::string_view path, std::int64_t rows, std::int64_t cols,
                         std::span<const std::int64_t> indptr,
                         std::span<const std::int32_t> indices, std::span<const double> values,
                         std::string_view values_name) {
  const std::string name = normalized(path, path_);
  require_new_object(name);
  check_csr(path_, name, rows, cols, indptr, indices, values.size());
  create_group(name);
  write_vector(join(name, "indptr"), indptr);
  write_vector(join(name, "indices"), indices);
  write_vector(join(name, values_name), values);
  const std::int64_t shape[2] = {rows, cols};
  write_int64_array_attribute(name, "shape", shape);
}

void Hdf5File::write_csr(std::string_view path, const CsrMatrix& matrix,
                         std::string_view values_name) {
  if (!matrix.isCompressed()) {
    CsrMatrix compressed = matrix;
    compressed.makeCompressed();
    write_csr(path, compressed, values_name);
    return;
  }
  const auto nnz = static_cast<std::size_t>(matrix.nonZeros());
  std::vector<std::int64_t> indptr(matrix.outerIndexPtr(),
                                   matrix.outerIndexPtr() + matrix.rows() + 1);
  write_csr(path, matrix.rows(), matrix.cols(), indptr,
            std::span<const std::int32_t>(matrix.innerIndexPtr(), nnz),
            std::span<const double>(matrix.valuePtr(), nnz), values_name);
}

CsrArrays Hdf5File::read_csr(std::string_view path, std::string_view values_name) const {
  const std::string name = normalized(path, path_);
  CsrArrays csr;
  const std::vector<std::int64_t> shape = read_int64_array_attribute(name, "shape");
  if (shape.size() != 2) {
    throw_store_error(path_, name, "attribute 'shape' does not have 2 elements");
  }
  csr.rows = shape[0];
  csr.cols = shape[1];
  csr.indptr = read_vector<std::int64_t>(join(name, "indptr"));
  csr.indices = read_vector<std::int32_t>(join(name, "indices"));
  csr.data = read_vector<double>(join(name, values_name));
  check_csr(path_, name, csr.rows, csr.cols, csr.indptr, csr.indices, csr.data.size());
  return csr;
}

CsrMatrix Hdf5File::read_csr_matrix(std::string_view path, std::string_view values_name) const {
  const CsrArrays csr = read_csr(path, values_name);
  constexpr auto kMaxIndex = std::numeric_limits<std::int32_t>::max();
  if (csr.rows > kMaxIndex || csr.cols > kMaxIndex ||
      csr.data.size() > static_cast<std::size_t>(kMaxIndex)) {
    throw_store_error(path_, normalized(path, path_),
                      "too large for a sparse matrix with int32 indices");
  }
  const std::vector<std::int32_t> outer(csr.indptr.begin(), csr.indptr.end());
  const Eigen::Map<const CsrMatrix> map(csr.rows, csr.cols,
                                        static_cast<Eigen::Index>(csr.data.size()), outer.data(),
                                        csr.indices.data(), csr.data.data());
  return CsrMatrix(map);
}

}  // namespace ggk::engine
