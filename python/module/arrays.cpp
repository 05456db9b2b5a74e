#include "python/module/arrays.hpp"

#include <limits>

namespace ggk::python {

namespace {

template <class Array>
void require_vector(const Array& array, std::string_view what) {
  if (array.ndim() != 1) {
    throw py::value_error(std::string(what) + " must be a 1-D array, not " +
                          std::to_string(array.ndim()) + "-D");
  }
}

// Moves `owner`'s storage behind a capsule: arrays built with it keep it alive.
template <class Matrix>
std::pair<Matrix*, py::capsule> owned(Matrix&& matrix) {
  auto* owner = new Matrix(std::move(matrix));
  return {owner, py::capsule(owner, [](void* p) { delete static_cast<Matrix*>(p); })};
}

template <class Matrix>
py::object to_scipy(Matrix&& matrix, const char* format) {
  matrix.makeCompressed();
  auto [owner, base] = owned(std::move(matrix));
  const auto nnz = static_cast<py::ssize_t>(owner->nonZeros());
  const auto outer = static_cast<py::ssize_t>(owner->outerSize()) + 1;
  py::array_t<double> data(nnz, owner->valuePtr(), base);
  py::array_t<std::int32_t> indices(nnz, owner->innerIndexPtr(), base);
  py::array_t<std::int32_t> indptr(outer, owner->outerIndexPtr(), base);
  py::module_ sparse = py::module_::import("scipy.sparse");
  return sparse.attr(format)(py::make_tuple(data, indices, indptr),
                             py::arg("shape") = py::make_tuple(owner->rows(), owner->cols()),
                             py::arg("copy") = false);
}

}  // namespace

std::span<const std::int32_t> int_span(const IntArray& array, std::string_view what) {
  require_vector(array, what);
  return {array.data(), static_cast<std::size_t>(array.size())};
}

std::span<const double> double_span(const DoubleArray& array, std::string_view what) {
  require_vector(array, what);
  return {array.data(), static_cast<std::size_t>(array.size())};
}

std::vector<std::uint8_t> flags_from(const py::handle& array, std::string_view what) {
  const auto flags = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(
      py::module_::import("numpy").attr("asarray")(array).attr("astype")("uint8"));
  if (!flags || flags.ndim() != 1) {
    throw py::value_error(std::string(what) + " must be a 1-D array of 0/1 flags");
  }
  return {flags.data(), flags.data() + flags.size()};
}

kernels::SparseRowMatrix sparse_rows_from(const py::handle& matrix, std::string_view what) {
  py::module_ sparse = py::module_::import("scipy.sparse");
  if (!sparse.attr("issparse")(matrix).cast<bool>()) {
    const auto dense = DoubleArray::ensure(matrix);
    if (!dense || dense.ndim() != 2) {
      throw py::value_error(std::string(what) +
                            " must be a scipy.sparse matrix or a 2-D array of floats");
    }
    const Eigen::Map<const kernels::RowMatrixXd> map(dense.data(), dense.shape(0), dense.shape(1));
    return map.sparseView();
  }
  // A canonical CSR copy (sorted indices, duplicates summed); the caller's matrix
  // is left as it is.
  py::object csr =
      sparse.attr("csr_matrix")(matrix, py::arg("dtype") = "float64", py::arg("copy") = true);
  csr.attr("sum_duplicates")();
  csr.attr("sort_indices")();
  const auto shape = csr.attr("shape").cast<std::pair<std::int64_t, std::int64_t>>();
  const auto data = DoubleArray::ensure(csr.attr("data"));
  const auto indptr = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(
      csr.attr("indptr"));
  const auto indices = IntArray::ensure(csr.attr("indices"));
  constexpr auto kMax = std::numeric_limits<std::int32_t>::max();
  if (shape.first > kMax || shape.second > kMax || data.size() > kMax) {
    throw py::value_error(std::string(what) + " is larger than the kernels' int32 indices");
  }
  const double* values = data.data();
  const std::int64_t* offsets = indptr.data();
  const std::int32_t* columns = indices.data();
  kernels::SparseRowMatrix result(shape.first, shape.second);
  result.reserve(static_cast<Eigen::Index>(data.size()));
  for (std::int64_t row = 0; row < shape.first; ++row) {
    result.startVec(row);
    for (std::int64_t e = offsets[row]; e < offsets[row + 1]; ++e) {
      if (values[e] != 0.0) result.insertBack(row, columns[e]) = values[e];
    }
  }
  result.finalize();
  return result;
}

py::array_t<double> to_numpy(Eigen::VectorXd&& values) {
  auto [owner, base] = owned(std::move(values));
  return py::array_t<double>(static_cast<py::ssize_t>(owner->size()), owner->data(), base);
}

py::object to_scipy_csr(kernels::SparseRowMatrix&& matrix) {
  return to_scipy(std::move(matrix), "csr_matrix");
}

py::object to_scipy_csc(kernels::SparseColMatrix&& matrix) {
  return to_scipy(std::move(matrix), "csc_matrix");
}

}  // namespace ggk::python
