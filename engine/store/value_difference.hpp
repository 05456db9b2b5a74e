#pragma once
// How far apart two readings of one dataset or attribute are, element by element,
// for `ggk diff --rtol R --atol A` (results_diff.hpp). Float elements are equal
// within tolerance when |a - b| <= atol + rtol |b| (b from the second file, as
// numpy.isclose), a NaN equals a NaN in the same place and an infinity only
// itself; integer, string and other elements are equal only when identical.
// The largest differences are those of the numeric elements that differ at all
// (bit for bit), with where they are, so that a report can say "weights moved by
// 9e-10" rather than "weights differ".
//
// Thread-safety: functions only.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"

namespace ggk::engine {

struct Tolerance {
  double rtol = 0.0;  // >= 0
  double atol = 0.0;  // >= 0
  bool exact() const { return rtol == 0.0 && atol == 0.0; }
};

// One element of a dataset or attribute: its row-major index within its part
// (the row, for a compound's member) and the two files' values.
struct ElementPlace {
  std::int64_t index = 0;
  std::string member;  // the compound member; empty otherwise
  double a = 0.0, b = 0.0;
  bool is_string = false;
  std::string text_a, text_b;  // string elements
};

struct ValuesDifference {
  std::int64_t elements = 0;      // elements compared (every part)
  std::int64_t differing = 0;     // not equal within the tolerance
  std::int64_t bitwise = 0;       // not identical (differing ones included)
  double largest_absolute = 0.0;  // |a - b|, over numeric elements that are not identical
  double largest_relative = 0.0;  // |a - b| / |b| (infinite where b = 0)
  std::optional<ElementPlace> absolute_at, relative_at;
  std::optional<ElementPlace> first_differing;  // the first element outside the tolerance
  bool equal() const { return differing == 0; }
};

// `a` and `b` must have equal types and shapes (Values::type and ::shape).
ValuesDifference compare_values(const Hdf5File::Values& a, const Hdf5File::Values& b,
                                const Tolerance& tolerance);

// "[3]", "[2, 5]" (row-major index in `shape`), or for a compound member
// "row 3, column sigma".
std::string element_place(const ElementPlace& place, const std::vector<std::int64_t>& shape);

// "37 of 1446 elements; largest absolute difference 9.1e-10 at [17] (0.41 vs 0.41),
// largest relative 2.2e-09 at [17]", or for strings "2 of 8 elements, first at
// row 3, column basis ("ggk" vs "ogk")".
std::string describe_difference(const ValuesDifference& difference,
                                const std::vector<std::int64_t>& shape);

}  // namespace ggk::engine
