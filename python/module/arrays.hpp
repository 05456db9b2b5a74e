#pragma once
// numpy and scipy.sparse in and out of the module, without copies where the
// layout allows.
//
// In: a C-contiguous float64 (int32) numpy array is read in place through a span or
// an Eigen::Ref; anything else (a list, another dtype, a Fortran-ordered array) is
// converted once. A sparse argument is a scipy.sparse matrix of any format or a 2-D
// array (exact zeros dropped); it becomes the kernels' SparseRowMatrix (a copy: the
// kernels own their tables).
// Out: a vector or matrix the kernels made is moved into a capsule that the numpy
// array keeps alive (no copy); a SparseRowMatrix becomes a scipy.sparse.csr_matrix
// over its own three arrays (no copy).
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "kernels/eigen_types.hpp"

namespace ggk::python {

namespace py = pybind11;

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<std::int32_t, py::array::c_style | py::array::forcecast>;
using DenseIn = Eigen::Ref<const kernels::RowMatrixXd>;

// A 1-D array's elements (ValueError naming `what` for another rank).
std::span<const std::int32_t> int_span(const IntArray& array, std::string_view what);
std::span<const double> double_span(const DoubleArray& array, std::string_view what);

// The array's 0/1 flags (any integer or bool dtype), one per element.
std::vector<std::uint8_t> flags_from(const py::handle& array, std::string_view what);

// A scipy.sparse matrix (any format) or a 2-D array as sparse rows: sorted column
// indices, duplicates summed, exact zeros dropped.
kernels::SparseRowMatrix sparse_rows_from(const py::handle& matrix, std::string_view what);

// Moves the vector into a 1-D numpy array that owns it.
template <class T>
py::array_t<T> to_numpy(std::vector<T>&& values) {
  auto* owner = new std::vector<T>(std::move(values));
  py::capsule base(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(static_cast<py::ssize_t>(owner->size()), owner->data(), base);
}

py::array_t<double> to_numpy(Eigen::VectorXd&& values);

// Moves the matrix into a scipy.sparse.csr_matrix over its own arrays.
py::object to_scipy_csr(kernels::SparseRowMatrix&& matrix);
py::object to_scipy_csc(kernels::SparseColMatrix&& matrix);

// The enumerator named `name` among `choices`; ValueError listing them otherwise.
template <class Enum>
Enum parse_choice(std::string_view what, const std::string& name,
                  std::initializer_list<std::pair<std::string_view, Enum>> choices) {
  std::string listed;
  for (const auto& [label, value] : choices) {
    if (label == name) return value;
    listed += (listed.empty() ? "\"" : ", \"") + std::string(label) + "\"";
  }
  throw py::value_error(std::string(what) + " must be one of " + listed + ", not \"" + name + "\"");
}

}  // namespace ggk::python
